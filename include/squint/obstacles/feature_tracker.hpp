// Feature detection and matching between two consecutive frames (paper §3.3 step 1): SIFT (the
// default), ORB and AKAZE with a ratio test, or pyramidal Lucas–Kanade tracking.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

namespace squint::obstacles {

enum class Detector { kSift, kOrb, kAkaze, kKlt };

// "sift", "orb", "akaze", "klt".
std::string DetectorName(Detector detector);
// Parses a detector name (case-sensitive, as above); false when unknown.
bool ParseDetector(const std::string& name, Detector* detector);

struct FeatureOptions {
  Detector detector = Detector::kSift;
  // Most features kept per image (SIFT, ORB: strongest first; KLT: corners tracked).
  int max_features = 400;
  // Lowe's ratio test: the best match is kept when its distance is below ratio × the second best.
  double ratio = 0.8;
  // SIFT contrast threshold (lower finds more features on weakly textured floors).
  double sift_contrast_threshold = 0.01;
  // SIFT octave layers.
  int sift_octave_layers = 3;
  // SIFT's first octave: -1 = OpenCV 4.6's own (the image doubled, 512×384 for 256×192: ≈ 3/4 of
  // SIFT's time), 0 = the native resolution (SIFT runs on the half-size image, whose doubled first
  // octave has the native size; keypoints are mapped back to full-size pixels).
  int sift_first_octave = 0;
  // ORB FAST threshold and pyramid levels (threshold 20 instead of 10: ≈ 15% faster; 3 levels
  // instead of 4: ≈ 10% faster, mean AUC 0.779 against 0.760 on ../shared/data/obstacles-*).
  int orb_fast_threshold = 20;
  int orb_levels = 3;
  // true: ORB keypoints kept by FAST score, descriptors unrotated (UprightOrbDetector: ≈ 38% fewer
  // instructions per bench pair than OpenCV's ORB, every figure of the detector table on
  // ../shared/data/obstacles-* at least as good; docs/obstacles.md); false: OpenCV's
  // ORB::detectAndCompute (twice the kept share of the FAST corners re-scored by Harris,
  // intensity-centroid orientation).
  bool orb_upright = true;
  // AKAZE detector threshold.
  double akaze_threshold = 0.0005;
  // KLT: Shi–Tomasi quality level, minimum corner spacing, window, pyramid levels, and the largest
  // forward–backward tracking error (pixels) accepted (KLT's analogue of the ratio test).
  double klt_quality = 0.005;
  double klt_min_distance_px = 5.0;
  // A 9-px window: LK on a 15-px window costs ≈ 10× more here (OpenCV 4.6, 400 corners) for
  // no better AUC on ../shared/data/obstacles-* (plain D 0.913 at 15 px, 0.915 at 9 px); 7 px is
  // slower (LK converges in more iterations).
  int klt_window_px = 9;
  // Pyramid levels above the image (31 mm steps move features a few pixels): 1 level is ≈ 23% faster
  // than 2 for mean AUC 0.909 against 0.912 on ../shared/data/obstacles-*.
  int klt_levels = 1;
  double klt_max_fb_error_px = 1.0;
  // Optionally refine descriptor matches (SIFT, ORB, AKAZE) to sub-pixel accuracy by Lucas–Kanade from the
  // matched position (keypoint positions are too coarse for the floor back-projection far away);
  // a match whose refinement fails or moves more than refine_max_shift_px is dropped.
  bool refine_subpixel = false;
  int refine_window_px = 11;
  double refine_max_shift_px = 2.0;
  // Matches whose image displacement exceeds this many pixels are dropped (consecutive frames of a
  // slowly moving robot; a mismatch across the image is never a real correspondence).
  double max_displacement_px = 60.0;

  // Empty when valid, otherwise what is wrong.
  std::string Validate() const;
};

// A correspondence between the earlier (previous) and the later (current) frame, in raw
// (distorted) pixel coordinates.
struct Match {
  cv::Point2f previous;
  cv::Point2f current;
};

// One class per detector; Track() finds correspondences between two 8-bit grey images of the same
// size. Implementations keep their buffers between calls.
class FeatureTracker {
 public:
  virtual ~FeatureTracker() = default;
  virtual Detector Kind() const = 0;
  // Appends nothing on failure; `matches` is cleared first.
  virtual void Track(const cv::Mat& previous, const cv::Mat& current, std::vector<Match>* matches) = 0;
};

// Shi–Tomasi corners (Shi & Tomasi 1994), the KLT tracker's detector: the smaller eigenvalue of the
// gradient structure tensor summed over a 3 × 3 block (3 × 3 Sobel gradients, reflected border),
// local maxima in a 3 × 3 neighbourhood above quality × the image's largest value, strongest first
// (equal values: the later pixel in raster order first), each at least min_distance from every
// corner kept before it, up to max_corners. The same corners in the same order as
// cv::goodFeaturesToTrack(image, corners, max_corners, quality, min_distance) with its defaults,
// with the buffers kept between calls (goodFeaturesToTrack allocates ≈ 1.4 MB per 256×192 call).
class ShiTomasiDetector {
 public:
  // `image`: 8-bit grey. `corners` is cleared first.
  void Detect(const cv::Mat& image, int max_corners, double quality, double min_distance,
              std::vector<cv::Point2f>* corners);

 private:
  struct Candidate {
    float value;
    int index;  // y · width + x
  };
  cv::Mat dx_, dy_, tensor_[3], eig_;  // tensor_: gx², gx·gy, gy²
  std::vector<Candidate> candidates_;
  std::vector<std::vector<cv::Point2f>> grid_;
};

// ORB keypoints kept by FAST score with upright (unrotated) descriptors, the ORB tracker's detector
// with FeatureOptions::orb_upright. The keypoints (positions, octave, size, response) are those of
// OpenCV 4.6's ORB with ORB::FAST_SCORE and the options' feature count, levels and FAST threshold
// (scale factor 1.2, edge threshold 15, patch 31), level by level and within a level row by row,
// with angle 0 instead of ORB's intensity-centroid orientation; the descriptors are ORB's
// (ORB::compute) for those keypoints. It runs OpenCV's pieces: the levels resized as ORB resizes
// them, cv::FAST on each level's interior only (ORB's own detector scans the 15-px border as well
// and drops its corners afterwards) and from a threshold near the level's cut down (the same
// corners: Detect), no Harris scores and no orientations, and ORB's descriptor level by level.
class UprightOrbDetector {
 public:
  // Options must be valid (SQUINT_ENSURE).
  explicit UprightOrbDetector(const FeatureOptions& options);
  // `image`: 8-bit grey. `keypoints` in full-size pixels, level by level; `descriptors` one 32-byte
  // row per keypoint (empty when there is none). With `from_last`, FAST starts each level from the
  // cut of the last call's image (a similar frame: fewer FAST passes); the result is the same.
  void Detect(const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints, cv::Mat* descriptors,
              bool from_last = false);

 private:
  static constexpr float kScaleFactor = 1.2f;
  static constexpr int kEdge = 15, kPatch = 31;
  int levels_, threshold_;
  cv::Ptr<cv::ORB> orb_;  // descriptors only
  std::vector<int> per_level_;
  std::vector<int> cuts_, last_cuts_;  // per level: the lowest kept FAST score (the threshold if all kept)
  bool have_cuts_ = false;
  std::vector<cv::Mat> pyramid_;
  std::vector<cv::KeyPoint> level_kp_;
  std::vector<float> scores_;
  cv::Mat level_desc_, descriptors_;
};

// The tracker the options ask for. Options must be valid (SQUINT_ENSURE).
std::unique_ptr<FeatureTracker> MakeFeatureTracker(const FeatureOptions& options);

}  // namespace squint::obstacles
