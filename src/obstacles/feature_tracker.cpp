// Feature trackers: SIFT / ORB / AKAZE descriptors matched with a ratio test, and pyramidal
// Lucas–Kanade tracking with a forward–backward check.
#include "squint/obstacles/feature_tracker.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <utility>

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

// Hamming distances between every row of `a` (rows of the result) and every row of `b` (columns),
// for binary descriptors (ORB: 32 bytes, AKAZE: 61 bytes). The x86 popcnt instruction is used when
// the CPU has it (8× faster than the portable bit count; OpenCV's BFMatcher calls one dispatched
// function per pair, ≈ 2 ms for 400 × 400 ORB descriptors against ≈ 0.25 ms here).
template <bool kHardware>
void HammingRows(const cv::Mat& a, const cv::Mat& b, cv::Mat* dist) {
  const int bytes = a.cols, words = bytes / 8;
  for (int i = 0; i < a.rows; ++i) {
    const unsigned char* p = a.ptr<unsigned char>(i);
    float* out = dist->ptr<float>(i);
    for (int j = 0; j < b.rows; ++j) {
      const unsigned char* q = b.ptr<unsigned char>(j);
      int d = 0;
      for (int w = 0; w < words; ++w) {
        std::uint64_t x, y;
        std::memcpy(&x, p + 8 * w, 8);
        std::memcpy(&y, q + 8 * w, 8);
        if constexpr (kHardware) d += __builtin_popcountll(x ^ y);
        else d += std::popcount(x ^ y);
      }
      for (int k = 8 * words; k < bytes; ++k) d += std::popcount(static_cast<unsigned>(p[k] ^ q[k]));
      out[j] = static_cast<float>(d);
    }
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("popcnt"))) void HammingRowsPopcnt(const cv::Mat& a, const cv::Mat& b, cv::Mat* dist) {
  HammingRows<true>(a, b, dist);
}
bool HasPopcnt() {
  static const bool has = __builtin_cpu_supports("popcnt");
  return has;
}
#endif

// dist(i, j) = distance between descriptor row i of `a` and row j of `b` (CV_32F).
void DescriptorDistances(const cv::Mat& a, const cv::Mat& b, int norm, cv::Mat* dist) {
  if (norm == cv::NORM_HAMMING) {
    dist->create(a.rows, b.rows, CV_32F);
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (HasPopcnt()) return HammingRowsPopcnt(a, b, dist);
#endif
    return HammingRows<false>(a, b, dist);
  }
  cv::batchDistance(a, b, *dist, CV_32F, cv::noArray(), norm);
}

// Detector + descriptor trackers share the matching: the distance matrix between the two frames'
// descriptors is computed once; a current keypoint's nearest previous keypoint is its match when it
// passes the ratio test against the second nearest and is mutual (that previous keypoint's own
// nearest current keypoint is this one). Same result as BFMatcher knnMatch(k = 2) + match() in the
// other direction, at half the distance computations.
class DescriptorTracker : public FeatureTracker {
 public:
  DescriptorTracker(Detector kind, cv::Ptr<cv::Feature2D> feature, int norm, const FeatureOptions& options)
      : kind_(kind), feature_(std::move(feature)), norm_(norm), options_(options) {}

  Detector Kind() const override { return kind_; }

  void Track(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) override {
    matches->clear();
    if (SameImage(previous, last_current_)) {  // streaming: the earlier frame was the last later one
      std::swap(kp_prev_, kp_cur_);
      cv::swap(desc_prev_, desc_cur_);
    } else {
      Detect(previous, &kp_prev_, &desc_prev_);
    }
    Detect(current, &kp_cur_, &desc_cur_);
    current.copyTo(last_current_);
    if (kp_prev_.size() < 2 || kp_cur_.size() < 2) return;
    DescriptorDistances(desc_cur_, desc_prev_, norm_, &dist_);
    // Nearest current row of every previous column (the mutual check).
    column_best_.assign(static_cast<std::size_t>(dist_.cols), -1);
    column_best_d_.assign(static_cast<std::size_t>(dist_.cols), std::numeric_limits<float>::infinity());
    for (int i = 0; i < dist_.rows; ++i) {
      const float* row = dist_.ptr<float>(i);
      for (int j = 0; j < dist_.cols; ++j)
        if (row[j] < column_best_d_[static_cast<std::size_t>(j)])
          column_best_d_[static_cast<std::size_t>(j)] = row[j], column_best_[static_cast<std::size_t>(j)] = i;
    }
    for (int i = 0; i < dist_.rows; ++i) {
      const float* row = dist_.ptr<float>(i);
      int best = -1;
      float d1 = std::numeric_limits<float>::infinity(), d2 = d1;
      for (int j = 0; j < dist_.cols; ++j) {
        if (row[j] < d1) d2 = d1, d1 = row[j], best = j;
        else if (row[j] < d2) d2 = row[j];
      }
      if (best < 0 || !(d1 < options_.ratio * d2)) continue;
      if (column_best_[static_cast<std::size_t>(best)] != i) continue;
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
  cv::Mat dist_;  // descriptor distances, current rows × previous columns
  std::vector<int> column_best_;
  std::vector<float> column_best_d_;
  std::vector<cv::Point2f> from_, to_, start_;
  std::vector<unsigned char> status_;
  std::vector<float> err_;

  // Keypoints and descriptors of one image; with a native first octave (SIFT), on the half-size
  // image, keypoints mapped back (half-size pixel i covers full-size pixels 2i and 2i + 1).
  void Detect(const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors) {
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
    cv::goodFeaturesToTrack(previous, corners_, options_.max_features, options_.klt_quality,
                            options_.klt_min_distance_px);
    if (corners_.empty()) return;
    const cv::Size window(options_.klt_window_px, options_.klt_window_px);
    // 10 iterations: LK converges in a few at this image motion; each one costs a window pass per point.
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.03);
    if (SameImage(previous, last_current_))  // streaming: reuse the last later frame's pyramid
      std::swap(pyr_prev_, pyr_cur_);
    else
      cv::buildOpticalFlowPyramid(previous, pyr_prev_, window, options_.klt_levels);
    cv::buildOpticalFlowPyramid(current, pyr_cur_, window, options_.klt_levels);
    current.copyTo(last_current_);
    cv::calcOpticalFlowPyrLK(pyr_prev_, pyr_cur_, corners_, tracked_, status_, err_, window, options_.klt_levels,
                             term);
    // Back from the tracked points, starting at the corners and on the full-resolution level only: a
    // consistent track converges there at once; an inconsistent one cannot get back within the bound.
    back_ = corners_;
    cv::calcOpticalFlowPyrLK(pyr_cur_, pyr_prev_, tracked_, back_, status_back_, err_, window, 0, term,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    const cv::Rect2f inside(0.f, 0.f, static_cast<float>(current.cols - 1), static_cast<float>(current.rows - 1));
    for (std::size_t i = 0; i < corners_.size(); ++i) {
      if (!status_[i] || !status_back_[i]) continue;
      if (!inside.contains(tracked_[i])) continue;
      if (!CloseEnough(corners_[i], back_[i], options_.klt_max_fb_error_px)) continue;
      if (!CloseEnough(corners_[i], tracked_[i], options_.max_displacement_px)) continue;
      matches->push_back({corners_[i], tracked_[i]});
    }
  }

 private:
  FeatureOptions options_;
  std::vector<cv::Point2f> corners_, tracked_, back_;
  std::vector<cv::Mat> pyr_prev_, pyr_cur_;
  cv::Mat last_current_;  // copy of the last later frame (pyr_cur_ is its pyramid)
  std::vector<unsigned char> status_, status_back_;
  std::vector<float> err_;
};

}  // namespace

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
