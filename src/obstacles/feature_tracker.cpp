// Feature trackers: SIFT / ORB / AKAZE descriptors matched with a ratio test, and pyramidal
// Lucas–Kanade tracking with a forward–backward check.
#include "squint/obstacles/feature_tracker.hpp"

#include <cmath>
#include <cstring>
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

// Detector + descriptor trackers share the matching: brute force, 2 nearest neighbours, ratio test,
// and mutual consistency (the best match in both directions).
class DescriptorTracker : public FeatureTracker {
 public:
  DescriptorTracker(Detector kind, cv::Ptr<cv::Feature2D> feature, int norm, const FeatureOptions& options)
      : kind_(kind), feature_(std::move(feature)), matcher_(norm, false), options_(options) {}

  Detector Kind() const override { return kind_; }

  void Track(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) override {
    matches->clear();
    if (SameImage(previous, last_current_)) {  // streaming: the earlier frame was the last later one
      std::swap(kp_prev_, kp_cur_);
      cv::swap(desc_prev_, desc_cur_);
    } else {
      feature_->detectAndCompute(previous, cv::noArray(), kp_prev_, desc_prev_);
    }
    feature_->detectAndCompute(current, cv::noArray(), kp_cur_, desc_cur_);
    current.copyTo(last_current_);
    if (kp_prev_.size() < 2 || kp_cur_.size() < 2) return;
    // OpenCV's knnMatch appends to its output: clear the buffers kept from the last pair, or stale
    // rows from earlier pairs index into this pair's keypoints.
    knn_.clear();
    back_.clear();
    matcher_.knnMatch(desc_cur_, desc_prev_, knn_, 2);
    matcher_.match(desc_prev_, desc_cur_, back_);
    for (const auto& pair : knn_) {
      if (pair.size() < 2) continue;
      const cv::DMatch& best = pair[0];
      if (!(best.distance < options_.ratio * pair[1].distance)) continue;
      // Mutual check: the previous keypoint's own best match must be this current keypoint.
      if (back_[static_cast<std::size_t>(best.trainIdx)].trainIdx != best.queryIdx) continue;
      const cv::Point2f& p = kp_prev_[static_cast<std::size_t>(best.trainIdx)].pt;
      const cv::Point2f& c = kp_cur_[static_cast<std::size_t>(best.queryIdx)].pt;
      if (!CloseEnough(p, c, options_.max_displacement_px)) continue;
      matches->push_back({p, c});
    }
    if (options_.refine_subpixel && !matches->empty()) Refine(previous, current, matches);
  }

 private:
  Detector kind_;
  cv::Ptr<cv::Feature2D> feature_;
  cv::BFMatcher matcher_;
  FeatureOptions options_;
  std::vector<cv::KeyPoint> kp_prev_, kp_cur_;
  cv::Mat desc_prev_, desc_cur_;
  cv::Mat last_current_;  // copy of the last later frame (kp_cur_, desc_cur_ are its detection)
  std::vector<std::vector<cv::DMatch>> knn_;
  std::vector<cv::DMatch> back_;
  std::vector<cv::Point2f> from_, to_, start_;
  std::vector<unsigned char> status_;
  std::vector<float> err_;

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
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03);
    if (SameImage(previous, last_current_))  // streaming: reuse the last later frame's pyramid
      std::swap(pyr_prev_, pyr_cur_);
    else
      cv::buildOpticalFlowPyramid(previous, pyr_prev_, window, options_.klt_levels);
    cv::buildOpticalFlowPyramid(current, pyr_cur_, window, options_.klt_levels);
    current.copyTo(last_current_);
    cv::calcOpticalFlowPyrLK(pyr_prev_, pyr_cur_, corners_, tracked_, status_, err_, window, options_.klt_levels,
                             term);
    back_ = corners_;
    cv::calcOpticalFlowPyrLK(pyr_cur_, pyr_prev_, tracked_, back_, status_back_, err_, window, options_.klt_levels,
                             term, cv::OPTFLOW_USE_INITIAL_FLOW);
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
