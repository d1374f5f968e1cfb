// Robust fundamental matrix (paper §3.3 steps 2–4): RANSAC, then F re-estimated from its inliers
// and the inlier set updated with the new F, until the set stops changing.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace squint::obstacles {

struct FundamentalOptions {
  // Largest point-to-epipolar-line distance (pixels, undistorted) of an inlier.
  double inlier_threshold_px = 1.0;
  // RANSAC confidence.
  double confidence = 0.999;
  // RANSAC iterations at most.
  int max_iterations = 2000;
  // Re-estimation rounds (steps 3–4) at most; they stop earlier once the inlier set is stable.
  int max_refinements = 10;
  // Fewest correspondences to attempt an estimate (8-point needs 8; more for robustness).
  int min_matches = 12;

  std::string Validate() const;
};

struct FundamentalResult {
  cv::Matx33d F;
  std::vector<unsigned char> inlier;  // one per input point, 1 = inlier
  int inliers = 0;
  int refinements = 0;  // rounds of steps 3–4 run
};

// Points are undistorted pixel coordinates (same K in both frames). None when there are fewer than
// `min_matches` points or no estimate is found.
std::optional<FundamentalResult> EstimateFundamental(const std::vector<cv::Point2f>& previous,
                                                     const std::vector<cv::Point2f>& current,
                                                     const FundamentalOptions& options);

// Symmetric point-to-epipolar-line distance in pixels (the larger of the two).
double EpipolarDistance(const cv::Matx33d& F, const cv::Point2f& previous, const cv::Point2f& current);

}  // namespace squint::obstacles
