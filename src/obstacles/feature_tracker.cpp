// Feature trackers: SIFT / ORB / AKAZE descriptors matched with a ratio test, and pyramidal
// Lucas–Kanade tracking with a forward–backward check.
#include "squint/obstacles/feature_tracker.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string DetectorName(Detector detector) {
  switch (detector) {
    case Detector::kSift: return "sift";
    case Detector::kOrb: return "orb";
    case Detector::kAkaze: return "akaze";
    case Detector::kKlt: return "klt";
  }
  return "?";
}

bool ParseDetector(const std::string& name, Detector* detector) {
  for (Detector d : {Detector::kSift, Detector::kOrb, Detector::kAkaze, Detector::kKlt}) {
    if (DetectorName(d) == name) {
      *detector = d;
      return true;
    }
  }
  return false;
}

std::string FeatureOptions::Validate() const {
  std::ostringstream why;
  if (max_features < 8) why << "max_features must be at least 8; ";
  if (!(ratio > 0.0 && ratio <= 1.0)) why << "ratio must lie in (0, 1]; ";
  if (!(sift_contrast_threshold > 0.0)) why << "sift_contrast_threshold must be positive; ";
  if (sift_octave_layers < 1) why << "sift_octave_layers must be at least 1; ";
  if (sift_first_octave != -1 && sift_first_octave != 0) why << "sift_first_octave must be -1 or 0; ";
  if (orb_fast_threshold < 1) why << "orb_fast_threshold must be at least 1; ";
  if (orb_levels < 1) why << "orb_levels must be at least 1; ";
  if (!(akaze_threshold > 0.0)) why << "akaze_threshold must be positive; ";
  if (!(klt_quality > 0.0 && klt_quality < 1.0)) why << "klt_quality must lie in (0, 1); ";
  if (!(klt_min_distance_px >= 0.0)) why << "klt_min_distance_px must not be negative; ";
  if (klt_window_px < 3) why << "klt_window_px must be at least 3; ";
  if (klt_levels < 0) why << "klt_levels must not be negative; ";
  if (!(klt_max_fb_error_px > 0.0)) why << "klt_max_fb_error_px must be positive; ";
  if (refine_window_px < 3) why << "refine_window_px must be at least 3; ";
  if (!(refine_max_shift_px > 0.0)) why << "refine_max_shift_px must be positive; ";
  if (!(max_displacement_px > 0.0)) why << "max_displacement_px must be positive; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

namespace {

// Byte-for-byte equality of two images (same size and type). Trackers keep a copy of the last later
// frame: when the next pair's earlier frame equals it (a stream of consecutive pairs), that frame's
// detection is reused instead of recomputed. Comparing contents (≈50 kB at 256×192, a few µs) rather
// than data pointers keeps this correct when the caller reuses one buffer for new frames.
bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty() || a.size() != b.size() || a.type() != b.type()) return false;
  const std::size_t row_bytes = static_cast<std::size_t>(a.cols) * a.elemSize();
  for (int r = 0; r < a.rows; ++r)
    if (std::memcmp(a.ptr(r), b.ptr(r), row_bytes) != 0) return false;
  return true;
}

bool CloseEnough(const cv::Point2f& a, const cv::Point2f& b, double max_px) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy <= max_px * max_px;
}

// Binary descriptors (ORB: 32 bytes, AKAZE: 61 bytes) packed into 64-bit words, zero-padded to a
// whole word (the padding XORs to zero), one descriptor after the other.
void PackWords(const cv::Mat& descriptors, std::vector<std::uint64_t>* words, int* words_per_row) {
  const int bytes = descriptors.cols, per_row = (bytes + 7) / 8;
  *words_per_row = per_row;
  words->assign(static_cast<std::size_t>(descriptors.rows) * static_cast<std::size_t>(per_row), 0);
  for (int i = 0; i < descriptors.rows; ++i)
    std::memcpy(words->data() + static_cast<std::size_t>(i) * static_cast<std::size_t>(per_row), descriptors.ptr(i),
                static_cast<std::size_t>(bytes));
}

// Nearest and second-nearest previous descriptor of every current one, and the nearest current
// descriptor of every previous one, by Hamming distance, in one pass over all pairs (no distance
// matrix). Ties keep the lower index, as a scan in index order with strict comparisons does.
// Float distances (SIFT) fill the *f vectors instead.
struct NearestTable {
  bool is_float = false;
  std::vector<int> row_best, row_d1, row_d2;  // per current descriptor
  std::vector<int> col_best, col_d;           // per previous descriptor
  std::vector<float> row_d1f, row_d2f, col_df;
  void Reset(int rows, int cols, bool floats) {
    is_float = floats;
    const auto r = static_cast<std::size_t>(rows), c = static_cast<std::size_t>(cols);
    row_best.assign(r, -1);
    col_best.assign(c, -1);
    if (floats) {
      row_d1f.assign(r, std::numeric_limits<float>::infinity());
      row_d2f.assign(r, std::numeric_limits<float>::infinity());
      col_df.assign(c, std::numeric_limits<float>::infinity());
    } else {
      row_d1.assign(r, std::numeric_limits<int>::max());
      row_d2.assign(r, std::numeric_limits<int>::max());
      col_d.assign(c, std::numeric_limits<int>::max());
    }
  }
  double D1(int i) const {
    const auto k = static_cast<std::size_t>(i);
    return is_float ? static_cast<double>(row_d1f[k]) : static_cast<double>(row_d1[k]);
  }
  double D2(int i) const {
    const auto k = static_cast<std::size_t>(i);
    return is_float ? static_cast<double>(row_d2f[k]) : static_cast<double>(row_d2[k]);
  }
};

// kWords > 0: words per descriptor known at compile time (ORB's 4); 0: `words` at run time.
template <int kWords, bool kHardware>
inline void HammingNearest(const std::uint64_t* cur, int rows, const std::uint64_t* prev, int cols, int words,
                           NearestTable* t) {
  if constexpr (kWords > 0) words = kWords;
  int* col_best = t->col_best.data();
  int* col_d = t->col_d.data();
  for (int i = 0; i < rows; ++i) {
    const std::uint64_t* p = cur + static_cast<std::size_t>(i) * static_cast<std::size_t>(words);
    std::uint64_t a[kWords > 0 ? kWords : 1];
    if constexpr (kWords > 0)
      for (int w = 0; w < kWords; ++w) a[w] = p[w];
    int best = -1, d1 = std::numeric_limits<int>::max(), d2 = d1;
    const std::uint64_t* q = prev;
    for (int j = 0; j < cols; ++j, q += words) {
      int d = 0;
      if constexpr (kWords > 0) {
        for (int w = 0; w < kWords; ++w) {
          if constexpr (kHardware) d += __builtin_popcountll(a[w] ^ q[w]);
          else d += std::popcount(a[w] ^ q[w]);
        }
      } else {
        for (int w = 0; w < words; ++w) {
          if constexpr (kHardware) d += __builtin_popcountll(p[w] ^ q[w]);
          else d += std::popcount(p[w] ^ q[w]);
        }
      }
      if (d < d1) d2 = d1, d1 = d, best = j;
      else if (d < d2) d2 = d;
      if (d < col_d[j]) col_d[j] = d, col_best[j] = i;
    }
    t->row_best[static_cast<std::size_t>(i)] = best;
    t->row_d1[static_cast<std::size_t>(i)] = d1;
    t->row_d2[static_cast<std::size_t>(i)] = d2;
  }
}

template <bool kHardware>
void HammingNearestAny(const std::uint64_t* cur, int rows, const std::uint64_t* prev, int cols, int words,
                       NearestTable* t) {
  if (words == 4) return HammingNearest<4, kHardware>(cur, rows, prev, cols, words, t);
  HammingNearest<0, kHardware>(cur, rows, prev, cols, words, t);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("popcnt"))) void HammingNearestPopcnt(const std::uint64_t* cur, int rows,
                                                            const std::uint64_t* prev, int cols, int words,
                                                            NearestTable* t) {
  HammingNearestAny<true>(cur, rows, prev, cols, words, t);
}
bool HasPopcnt() {
  static const bool has = __builtin_cpu_supports("popcnt");
  return has;
}
bool HasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// ORB's 32-byte descriptors with AVX2: eight distances per step (nibble-table bit count, byte sums
// per 64-bit lane, lanes summed), the column minima updated eight at a time; a row's best two are
// updated in index order only when one of the eight beats its current second best. Same result as
// HammingNearest<4, ...> (integer arithmetic, same tie rule).
__attribute__((target("avx2,popcnt"))) void HammingNearest32Avx2(const std::uint64_t* cur, int rows,
                                                                 const std::uint64_t* prev, int cols,
                                                                 NearestTable* t) {
  const __m256i lut = _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2,
                                       3, 2, 3, 3, 4);
  const __m256i low4 = _mm256_set1_epi8(0x0f);
  const __m256i zero = _mm256_setzero_si256();
  int* col_best = t->col_best.data();
  int* col_d = t->col_d.data();
  alignas(32) int d8[8];
  for (int i = 0; i < rows; ++i) {
    const std::uint64_t* p = cur + 4 * static_cast<std::size_t>(i);
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    const __m256i vi = _mm256_set1_epi32(i);
    int best = -1, d1 = std::numeric_limits<int>::max(), d2 = d1;
    auto scalar = [&](int j, int d) {
      if (d < d1) d2 = d1, d1 = d, best = j;
      else if (d < d2) d2 = d;
    };
    int j = 0;
    for (; j + 8 <= cols; j += 8) {
      // Per descriptor k: the bit count of a ^ prev[j + k] as four partial byte sums, one per 64-bit lane.
      __m256i sums[8];
      for (int k = 0; k < 8; ++k) {
        const __m256i x = _mm256_xor_si256(
            a, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(prev + 4 * static_cast<std::size_t>(j + k))));
        const __m256i counts = _mm256_add_epi8(_mm256_shuffle_epi8(lut, _mm256_and_si256(x, low4)),
                                               _mm256_shuffle_epi8(lut, _mm256_and_si256(_mm256_srli_epi16(x, 4), low4)));
        sums[k] = _mm256_sad_epu8(counts, zero);
      }
      // Lane sums of descriptors k and k + 1 in the low and high halves of each 64-bit lane, then
      // the lanes added up: d holds the eight distances in order.
      const __m256i a01 = _mm256_or_si256(sums[0], _mm256_slli_epi64(sums[1], 32));
      const __m256i a23 = _mm256_or_si256(sums[2], _mm256_slli_epi64(sums[3], 32));
      const __m256i a45 = _mm256_or_si256(sums[4], _mm256_slli_epi64(sums[5], 32));
      const __m256i a67 = _mm256_or_si256(sums[6], _mm256_slli_epi64(sums[7], 32));
      const __m256i c = _mm256_add_epi32(_mm256_unpacklo_epi64(a01, a23), _mm256_unpackhi_epi64(a01, a23));
      const __m256i e = _mm256_add_epi32(_mm256_unpacklo_epi64(a45, a67), _mm256_unpackhi_epi64(a45, a67));
      const __m256i d = _mm256_add_epi32(_mm256_permute2x128_si256(c, e, 0x20), _mm256_permute2x128_si256(c, e, 0x31));
      __m256i* cd_ptr = reinterpret_cast<__m256i*>(col_d + j);
      __m256i* cb_ptr = reinterpret_cast<__m256i*>(col_best + j);
      const __m256i cd = _mm256_loadu_si256(cd_ptr);
      const __m256i lower = _mm256_cmpgt_epi32(cd, d);  // d < column minimum so far
      _mm256_storeu_si256(cd_ptr, _mm256_min_epi32(cd, d));
      _mm256_storeu_si256(cb_ptr, _mm256_blendv_epi8(_mm256_loadu_si256(cb_ptr), vi, lower));
      const __m256i beats = _mm256_cmpgt_epi32(_mm256_set1_epi32(d2), d);
      if (_mm256_testz_si256(beats, beats)) continue;
      _mm256_store_si256(reinterpret_cast<__m256i*>(d8), d);
      for (int k = 0; k < 8; ++k) scalar(j + k, d8[k]);
    }
    for (; j < cols; ++j) {
      const std::uint64_t* q = prev + 4 * static_cast<std::size_t>(j);
      const int d = __builtin_popcountll(p[0] ^ q[0]) + __builtin_popcountll(p[1] ^ q[1]) +
                    __builtin_popcountll(p[2] ^ q[2]) + __builtin_popcountll(p[3] ^ q[3]);
      scalar(j, d);
      if (d < col_d[j]) col_d[j] = d, col_best[j] = i;
    }
    t->row_best[static_cast<std::size_t>(i)] = best;
    t->row_d1[static_cast<std::size_t>(i)] = d1;
    t->row_d2[static_cast<std::size_t>(i)] = d2;
  }
}
#endif

// Detector + descriptor trackers share the matching: the distance matrix between the two frames'
// descriptors is computed once; a current keypoint's nearest previous keypoint is its match when it
// passes the ratio test against the second nearest and is mutual (that previous keypoint's own
// nearest current keypoint is this one). Same result as BFMatcher knnMatch(k = 2) + match() in the
// other direction, at half the distance computations.
class DescriptorTracker : public FeatureTracker {
 public:
  DescriptorTracker(Detector kind, cv::Ptr<cv::Feature2D> feature, int norm, const FeatureOptions& options)
      : kind_(kind), feature_(std::move(feature)), norm_(norm), options_(options) {
    if (kind_ == Detector::kOrb && options_.orb_upright) upright_ = std::make_unique<UprightOrbDetector>(options_);
  }

  Detector Kind() const override { return kind_; }

  void Track(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) override {
    matches->clear();
    if (SameImage(previous, last_current_)) {  // streaming: the earlier frame was the last later one
      std::swap(kp_prev_, kp_cur_);
      cv::swap(desc_prev_, desc_cur_);
    } else {
      Detect(previous, &kp_prev_, &desc_prev_, false);
    }
    Detect(current, &kp_cur_, &desc_cur_, true);  // upright ORB: FAST starts from the earlier frame's cuts
    current.copyTo(last_current_);
    if (kp_prev_.size() < 2 || kp_cur_.size() < 2) return;
    const int rows = desc_cur_.rows, cols = desc_prev_.rows;
    nearest_.Reset(rows, cols, norm_ != cv::NORM_HAMMING);
    if (norm_ == cv::NORM_HAMMING) {
      int words = 0;
      PackWords(desc_cur_, &words_cur_, &words);
      PackWords(desc_prev_, &words_prev_, &words);
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      if (words == 4 && HasAvx2() && HasPopcnt())
        HammingNearest32Avx2(words_cur_.data(), rows, words_prev_.data(), cols, &nearest_);
      else if (HasPopcnt())
        HammingNearestPopcnt(words_cur_.data(), rows, words_prev_.data(), cols, words, &nearest_);
      else
#endif
        HammingNearestAny<false>(words_cur_.data(), rows, words_prev_.data(), cols, words, &nearest_);
    } else {
      FloatNearest();
    }
    for (int i = 0; i < rows; ++i) {
      const int best = nearest_.row_best[static_cast<std::size_t>(i)];
      const double d1 = nearest_.D1(i), d2 = nearest_.D2(i);
      if (best < 0 || !(d1 < options_.ratio * d2)) continue;
      if (nearest_.col_best[static_cast<std::size_t>(best)] != i) continue;
      const cv::Point2f& p = kp_prev_[static_cast<std::size_t>(best)].pt;
      const cv::Point2f& c = kp_cur_[static_cast<std::size_t>(i)].pt;
      if (!CloseEnough(p, c, options_.max_displacement_px)) continue;
      matches->push_back({p, c});
    }
    if (options_.refine_subpixel && !matches->empty()) Refine(previous, current, matches);
  }

 private:
  Detector kind_;
  cv::Ptr<cv::Feature2D> feature_;
  int norm_;
  FeatureOptions options_;
  std::vector<cv::KeyPoint> kp_prev_, kp_cur_;
  cv::Mat desc_prev_, desc_cur_;
  cv::Mat last_current_;  // copy of the last later frame (kp_cur_, desc_cur_ are its detection)
  cv::Mat half_;          // the half-size image (SIFT with a native first octave)
  cv::Mat dist_;  // float descriptor distances (SIFT), current rows × previous columns
  std::vector<std::uint64_t> words_cur_, words_prev_;  // binary descriptors as 64-bit words
  NearestTable nearest_;
  std::unique_ptr<UprightOrbDetector> upright_;  // ORB with orb_upright
  std::vector<cv::Point2f> from_, to_, start_;
  std::vector<unsigned char> status_;
  std::vector<float> err_;

  // The nearest-neighbour table from the float distance matrix (L2: SIFT).
  void FloatNearest() {
    cv::batchDistance(desc_cur_, desc_prev_, dist_, CV_32F, cv::noArray(), norm_);
    std::vector<float>& col_d = nearest_.col_df;
    for (int i = 0; i < dist_.rows; ++i) {
      const float* row = dist_.ptr<float>(i);
      int best = -1;
      float d1 = std::numeric_limits<float>::infinity(), d2 = d1;
      for (int j = 0; j < dist_.cols; ++j) {
        if (row[j] < d1) d2 = d1, d1 = row[j], best = j;
        else if (row[j] < d2) d2 = row[j];
        if (row[j] < col_d[static_cast<std::size_t>(j)])
          col_d[static_cast<std::size_t>(j)] = row[j], nearest_.col_best[static_cast<std::size_t>(j)] = i;
      }
      nearest_.row_best[static_cast<std::size_t>(i)] = best;
      nearest_.row_d1f[static_cast<std::size_t>(i)] = d1;
      nearest_.row_d2f[static_cast<std::size_t>(i)] = d2;
    }
  }

  // Keypoints and descriptors of one image; with a native first octave (SIFT), on the half-size
  // image, keypoints mapped back (half-size pixel i covers full-size pixels 2i and 2i + 1).
  void Detect(const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors, bool from_last) {
    if (upright_) {
      upright_->Detect(image, keypoints, descriptors, from_last);
      return;
    }
    if (!(kind_ == Detector::kSift && options_.sift_first_octave == 0)) {
      feature_->detectAndCompute(image, cv::noArray(), *keypoints, *descriptors);
      return;
    }
    cv::resize(image, half_, cv::Size(image.cols / 2, image.rows / 2), 0.0, 0.0, cv::INTER_AREA);
    feature_->detectAndCompute(half_, cv::noArray(), *keypoints, *descriptors);
    for (cv::KeyPoint& k : *keypoints) {
      k.pt = {2.f * k.pt.x + 0.5f, 2.f * k.pt.y + 0.5f};
      k.size *= 2.f;
    }
  }

  // Lucas–Kanade from the matched position: the earlier point stays, the later one moves to the
  // sub-pixel optimum of the local image patch.
  void Refine(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) {
    from_.clear();
    to_.clear();
    for (const Match& m : *matches) from_.push_back(m.previous), to_.push_back(m.current);
    start_ = to_;
    const cv::Size window(options_.refine_window_px, options_.refine_window_px);
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.001);
    cv::calcOpticalFlowPyrLK(previous, current, from_, to_, status_, err_, window, 0, term,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < matches->size(); ++i) {
      if (!status_[i] || !CloseEnough(start_[i], to_[i], options_.refine_max_shift_px)) continue;
      (*matches)[kept++] = {from_[i], to_[i]};
    }
    matches->resize(kept);
  }
};

// Shi–Tomasi corners in the earlier frame tracked into the later one, kept when tracking back lands
// within klt_max_fb_error_px of the start.
class KltTracker : public FeatureTracker {
 public:
  explicit KltTracker(const FeatureOptions& options) : options_(options) {}
  Detector Kind() const override { return Detector::kKlt; }

  void Track(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) override {
    matches->clear();
    corners_detector_.Detect(previous, options_.max_features, options_.klt_quality, options_.klt_min_distance_px,
                             &corners_);
    if (corners_.empty()) return;
    const cv::Size window(options_.klt_window_px, options_.klt_window_px);
    // At most 10 iterations, until a step is below 0.1 px: LK converges in a few at this image motion;
    // each one costs a window pass per point. 0.1 px instead of 0.03: ≈ 20% fewer LK instructions
    // per pair, every figure on ../shared/data/obstacles-* at least as good (docs/obstacles.md).
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.1);
    if (SameImage(previous, last_current_))  // streaming: reuse the last later frame's pyramid
      std::swap(pyr_prev_, pyr_cur_);
    else
      cv::buildOpticalFlowPyramid(previous, pyr_prev_, window, options_.klt_levels);
    cv::buildOpticalFlowPyramid(current, pyr_cur_, window, options_.klt_levels);
    current.copyTo(last_current_);
    // No error output: OpenCV computes it in an extra window pass per point, and it is not used.
    cv::calcOpticalFlowPyrLK(pyr_prev_, pyr_cur_, corners_, tracked_, status_, cv::noArray(), window,
                             options_.klt_levels, term);
    // Back from the tracked points, starting at the corners and on the full-resolution level only: a
    // consistent track converges there at once; an inconsistent one cannot get back within the bound.
    // Only tracks that pass the forward tests go back (LK treats every point on its own, so this
    // changes no result).
    const cv::Rect2f inside(0.f, 0.f, static_cast<float>(current.cols - 1), static_cast<float>(current.rows - 1));
    start_.clear();
    end_.clear();
    kept_.clear();
    for (std::size_t i = 0; i < corners_.size(); ++i) {
      if (!status_[i] || !inside.contains(tracked_[i])) continue;
      if (!CloseEnough(corners_[i], tracked_[i], options_.max_displacement_px)) continue;
      kept_.push_back(i);
      start_.push_back(tracked_[i]);
      end_.push_back(corners_[i]);
    }
    if (kept_.empty()) return;
    cv::calcOpticalFlowPyrLK(pyr_cur_, pyr_prev_, start_, end_, status_back_, cv::noArray(), window, 0, term,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    for (std::size_t k = 0; k < kept_.size(); ++k) {
      const std::size_t i = kept_[k];
      if (!status_back_[k]) continue;
      if (!CloseEnough(corners_[i], end_[k], options_.klt_max_fb_error_px)) continue;
      matches->push_back({corners_[i], tracked_[i]});
    }
  }

 private:
  FeatureOptions options_;
  ShiTomasiDetector corners_detector_;
  std::vector<cv::Point2f> corners_, tracked_;
  std::vector<cv::Point2f> start_, end_;  // the backward tracks: from the tracked points, ending near the corners
  std::vector<std::size_t> kept_;         // their corner indices
  std::vector<cv::Mat> pyr_prev_, pyr_cur_;
  cv::Mat last_current_;  // copy of the last later frame (pyr_cur_ is its pyramid)
  std::vector<unsigned char> status_, status_back_;
};

}  // namespace

void ShiTomasiDetector::Detect(const cv::Mat& image, int max_corners, double quality, double min_distance,
                             std::vector<cv::Point2f>* corners) {
  corners->clear();
  const int w = image.cols, h = image.rows;
  if (w < 3 || h < 3) return;
  // Gradients scaled as OpenCV scales them for a 3 × 3 block: 1 / (4 · 3 · 255).
  const double scale = 1.0 / (4.0 * 3.0 * 255.0);
  cv::Sobel(image, dx_, CV_32F, 1, 0, 3, scale, 0, cv::BORDER_DEFAULT);
  cv::Sobel(image, dy_, CV_32F, 0, 1, 3, scale, 0, cv::BORDER_DEFAULT);
  // The structure tensor's three planes, each summed over the 3 × 3 block (per element the same sums
  // as OpenCV's three-channel box filter).
  for (cv::Mat& m : tensor_) m.create(h, w, CV_32F);
  for (int y = 0; y < h; ++y) {
    const float* gx = dx_.ptr<float>(y);
    const float* gy = dy_.ptr<float>(y);
    float* xx = tensor_[0].ptr<float>(y);
    float* xy = tensor_[1].ptr<float>(y);
    float* yy = tensor_[2].ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      xx[x] = gx[x] * gx[x];
      xy[x] = gx[x] * gy[x];
      yy[x] = gy[x] * gy[x];
    }
  }
  for (cv::Mat& m : tensor_)
    cv::boxFilter(m, m, CV_32F, cv::Size(3, 3), cv::Point(-1, -1), false, cv::BORDER_DEFAULT);
  // Smaller eigenvalue (a + c) − sqrt((a − c)² + b²) with a, c half the diagonal, b the off-diagonal.
  eig_.create(h, w, CV_32F);
  float largest = -std::numeric_limits<float>::infinity();
  for (int y = 0; y < h; ++y) {
    const float* xx = tensor_[0].ptr<float>(y);
    const float* xy = tensor_[1].ptr<float>(y);
    const float* yy = tensor_[2].ptr<float>(y);
    float* e = eig_.ptr<float>(y);
    int x = 0;
#if defined(__SSE2__)
    const __m128 half = _mm_set1_ps(0.5f);
    __m128 top = _mm_set1_ps(largest);
    for (; x + 4 <= w; x += 4) {
      const __m128 a = _mm_mul_ps(_mm_loadu_ps(xx + x), half), b = _mm_loadu_ps(xy + x);
      const __m128 c = _mm_mul_ps(_mm_loadu_ps(yy + x), half), d = _mm_sub_ps(a, c);
      const __m128 v = _mm_sub_ps(_mm_add_ps(a, c), _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(d, d), _mm_mul_ps(b, b))));
      _mm_storeu_ps(e + x, v);
      top = _mm_max_ps(top, v);
    }
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, top);
    for (float l : lanes) largest = std::max(largest, l);
#endif
    for (; x < w; ++x) {
      const float a = xx[x] * 0.5f, b = xy[x], c = yy[x] * 0.5f;
      const float d = a - c;
      e[x] = (a + c) - std::sqrt(d * d + b * b);
      largest = std::max(largest, e[x]);
    }
  }
  // Values not above the threshold count as 0, as in a thresholded map; a local maximum is not below
  // any of its eight neighbours.
  const float threshold = static_cast<float>(static_cast<double>(largest) * quality);
  candidates_.clear();
  if (threshold >= 0.f) {
    // Then a value above the threshold is not below a neighbour's thresholded value exactly when it
    // is not below the neighbour's value.
    for (int y = 1; y < h - 1; ++y) {
      const float* up = eig_.ptr<float>(y - 1);
      const float* row = eig_.ptr<float>(y);
      const float* down = eig_.ptr<float>(y + 1);
      int x = 1;
#if defined(__SSE2__)
      const __m128 t = _mm_set1_ps(threshold);
      for (; x + 4 <= w - 1; x += 4) {
        const __m128 v = _mm_loadu_ps(row + x);
        __m128 ok = _mm_cmpgt_ps(v, t);
        if (_mm_movemask_ps(ok) == 0) continue;
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(row + x - 1)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(row + x + 1)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(up + x - 1)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(up + x)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(up + x + 1)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(down + x - 1)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(down + x)));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(v, _mm_loadu_ps(down + x + 1)));
        for (int bits = _mm_movemask_ps(ok); bits != 0; bits &= bits - 1) {
          const int k = std::countr_zero(static_cast<unsigned>(bits));
          candidates_.push_back({row[x + k], y * w + x + k});
        }
      }
#endif
      for (; x < w - 1; ++x) {
        const float v = row[x];
        if (!(v > threshold)) continue;
        if (v < row[x - 1] || v < row[x + 1] || v < up[x - 1] || v < up[x] || v < up[x + 1] || v < down[x - 1] ||
            v < down[x] || v < down[x + 1])
          continue;
        candidates_.push_back({v, y * w + x});
      }
    }
  } else {
    auto kept = [threshold](float v) { return v > threshold ? v : 0.f; };
    for (int y = 1; y < h - 1; ++y) {
      const float* up = eig_.ptr<float>(y - 1);
      const float* row = eig_.ptr<float>(y);
      const float* down = eig_.ptr<float>(y + 1);
      for (int x = 1; x < w - 1; ++x) {
        const float v = kept(row[x]);
        if (v == 0.f) continue;
        if (v < kept(row[x - 1]) || v < kept(row[x + 1]) || v < kept(up[x - 1]) || v < kept(up[x]) ||
            v < kept(up[x + 1]) || v < kept(down[x - 1]) || v < kept(down[x]) || v < kept(down[x + 1]))
          continue;
        candidates_.push_back({v, y * w + x});
      }
    }
  }
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& p, const Candidate& q) {
    return p.value > q.value || (p.value == q.value && p.index > q.index);
  });
  const int max_n = max_corners > 0 ? max_corners : std::numeric_limits<int>::max();
  if (min_distance < 1.0) {
    for (const Candidate& c : candidates_) {
      if (static_cast<int>(corners->size()) == max_n) break;
      corners->emplace_back(static_cast<float>(c.index % w), static_cast<float>(c.index / w));
    }
    return;
  }
  // A grid of min_distance-sized cells: a candidate is checked against the corners of its cell and
  // the eight around it.
  const int cell = cvRound(min_distance);
  const int gw = (w + cell - 1) / cell, gh = (h + cell - 1) / cell;
  grid_.resize(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  for (auto& g : grid_) g.clear();
  const double min_d2 = min_distance * min_distance;
  for (const Candidate& c : candidates_) {
    const int x = c.index % w, y = c.index / w;
    const int cx = x / cell, cy = y / cell;
    bool good = true;
    for (int yy = std::max(0, cy - 1); good && yy <= std::min(gh - 1, cy + 1); ++yy)
      for (int xx = std::max(0, cx - 1); good && xx <= std::min(gw - 1, cx + 1); ++xx)
        for (const cv::Point2f& q : grid_[static_cast<std::size_t>(yy * gw + xx)]) {
          const float ddx = static_cast<float>(x) - q.x, ddy = static_cast<float>(y) - q.y;
          if (ddx * ddx + ddy * ddy < min_d2) {
            good = false;
            break;
          }
        }
    if (!good) continue;
    const cv::Point2f p(static_cast<float>(x), static_cast<float>(y));
    grid_[static_cast<std::size_t>(cy * gw + cx)].push_back(p);
    corners->push_back(p);
    if (static_cast<int>(corners->size()) == max_n) break;
  }
}

UprightOrbDetector::UprightOrbDetector(const FeatureOptions& options)
    : levels_(options.orb_levels),
      threshold_(options.orb_fast_threshold),
      orb_(cv::ORB::create(options.max_features, kScaleFactor, options.orb_levels, kEdge, 0, 2, cv::ORB::FAST_SCORE,
                           kPatch, options.orb_fast_threshold)),
      per_level_(static_cast<std::size_t>(options.orb_levels)),
      cuts_(static_cast<std::size_t>(options.orb_levels)),
      pyramid_(static_cast<std::size_t>(options.orb_levels)) {
  SQUINT_ENSURE(options.Validate().empty(), options.Validate());
  // ORB's split of the feature count over the levels: a geometric series, the rest on the last level
  // (float arithmetic as in OpenCV 4.6's computeKeyPoints).
  const auto factor = static_cast<float>(1.0 / static_cast<double>(kScaleFactor));
  float per_scale = static_cast<float>(options.max_features) * (1 - factor) /
                    (1 - static_cast<float>(std::pow(static_cast<double>(factor), static_cast<double>(levels_))));
  int sum = 0;
  for (int l = 0; l + 1 < levels_; ++l) {
    per_level_[static_cast<std::size_t>(l)] = cvRound(per_scale);
    sum += per_level_[static_cast<std::size_t>(l)];
    per_scale *= factor;
  }
  per_level_.back() = std::max(options.max_features - sum, 0);
}

void UprightOrbDetector::Detect(const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors,
                                bool from_last) {
  keypoints->clear();
  descriptors_.resize(0);
  const bool hinted = from_last && have_cuts_;
  std::fill(cuts_.begin(), cuts_.end(), threshold_);
  // FAST reads 3 px around a pixel and compares its score with the 8 around it: corners from 15 px
  // inwards need the level from 11 px inwards.
  constexpr int kMargin = kEdge - 4;
  for (int l = 0; l < levels_; ++l) {
    const auto li = static_cast<std::size_t>(l);
    // ORB's level scale and size (float, as OpenCV computes them).
    const auto scale = static_cast<float>(std::pow(static_cast<double>(kScaleFactor), static_cast<double>(l)));
    const float inv_scale = 1.0f / scale;
    const cv::Size size(cvRound(static_cast<float>(image.cols) * inv_scale),
                        cvRound(static_cast<float>(image.rows) * inv_scale));
    cv::Mat& level = pyramid_[li];
    if (l == 0)
      level = image;
    else
      cv::resize(pyramid_[li - 1], level, size, 0.0, 0.0, cv::INTER_LINEAR_EXACT);
    const int n = per_level_[li];
    if (size.width <= 2 * kEdge || size.height <= 2 * kEdge) break;  // no keypoint here or further up
    if (n == 0) continue;
    // The level's kept corners are those with a FAST score of at least the n-th best score c. A
    // corner's score does not depend on the threshold, and a corner with score s ≥ t survives the
    // non-maximum test at threshold t exactly when it survives it at the options' threshold (its
    // neighbours below t score less than s either way): FAST at any t ≤ c finds all of them. So
    // FAST starts at a threshold below the cut that a similar frame had (3/4 of it: the pair's
    // earlier frame for the later one, the level below for the earlier frame's upper levels, 4 ×
    // the threshold for its level 0) and halves it, down to the options' threshold, until it finds n
    // corners: the same keypoints at any start; only the time differs.
    int t = threshold_;
    if (hinted)
      t = std::max(threshold_, last_cuts_[li] * 3 / 4);
    else
      t = l == 0 ? 4 * threshold_ : std::max(threshold_, cuts_[li - 1] * 3 / 4);
    const cv::Rect inner(kMargin, kMargin, size.width - 2 * kMargin, size.height - 2 * kMargin);
    for (;;) {
      cv::FAST(level(inner), level_kp_, t, true);
      for (cv::KeyPoint& k : level_kp_) k.pt += cv::Point2f(static_cast<float>(kMargin), static_cast<float>(kMargin));
      cv::KeyPointsFilter::runByImageBorder(level_kp_, size, kEdge);
      if (static_cast<int>(level_kp_.size()) >= n || t == threshold_) break;
      t = std::max(threshold_, t / 2);
    }
    if (level_kp_.empty()) continue;
    // The n best by score and every corner tied with the n-th (as KeyPointsFilter::retainBest keeps
    // them), in FAST's order (row by row).
    if (static_cast<int>(level_kp_.size()) > n) {
      scores_.clear();
      for (const cv::KeyPoint& k : level_kp_) scores_.push_back(k.response);
      std::nth_element(scores_.begin(), scores_.begin() + (n - 1), scores_.end(), std::greater<float>());
      const float cut = scores_[static_cast<std::size_t>(n - 1)];
      level_kp_.erase(std::remove_if(level_kp_.begin(), level_kp_.end(),
                                     [cut](const cv::KeyPoint& k) { return k.response < cut; }),
                      level_kp_.end());
      cuts_[li] = static_cast<int>(cut);
    }
    for (cv::KeyPoint& k : level_kp_) k.angle = 0.f;
    // ORB's descriptors of this level's keypoints, with the level image as ORB's own level 0: the
    // same reflected border, 7 × 7 Gaussian blur and samples as in ORB's level l (the unrotated
    // pattern stays within 15 px of a keypoint), without resizing a whole pyramid again.
    orb_->detectAndCompute(level, cv::noArray(), level_kp_, level_desc_, true);
    descriptors_.push_back(level_desc_);
    for (cv::KeyPoint& k : level_kp_) {
      k.octave = l;
      k.size = static_cast<float>(kPatch) * scale;
      k.pt *= scale;
      keypoints->push_back(k);
    }
  }
  last_cuts_ = cuts_;
  have_cuts_ = true;
  if (keypoints->empty())
    descriptors->release();
  else
    descriptors_.copyTo(*descriptors);
}

std::unique_ptr<FeatureTracker> MakeFeatureTracker(const FeatureOptions& options) {
  SQUINT_ENSURE(options.Validate().empty(), options.Validate());
  switch (options.detector) {
    case Detector::kSift:
      return std::make_unique<DescriptorTracker>(
          Detector::kSift,
          cv::SIFT::create(options.max_features, options.sift_octave_layers, options.sift_contrast_threshold),
          cv::NORM_L2, options);
    case Detector::kOrb:
      return std::make_unique<DescriptorTracker>(
          Detector::kOrb,
          cv::ORB::create(options.max_features, 1.2f, options.orb_levels, 15, 0, 2, cv::ORB::HARRIS_SCORE, 31,
                          options.orb_fast_threshold),
          cv::NORM_HAMMING, options);
    case Detector::kAkaze: {
      auto akaze = cv::AKAZE::create();
      akaze->setThreshold(options.akaze_threshold);
      return std::make_unique<DescriptorTracker>(Detector::kAkaze, akaze, cv::NORM_HAMMING, options);
    }
    case Detector::kKlt: return std::make_unique<KltTracker>(options);
  }
  return nullptr;
}

}  // namespace squint::obstacles
