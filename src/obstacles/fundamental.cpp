// Robust fundamental matrix: OpenCV RANSAC, then 8-point re-estimation on the inliers and inlier
// update by epipolar distance, repeated until the inlier set is stable (paper §3.3 steps 2–4).
#include "squint/obstacles/fundamental.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <opencv2/calib3d.hpp>

namespace squint::obstacles {

std::string FundamentalOptions::Validate() const {
  std::ostringstream why;
  if (!(inlier_threshold_px > 0.0)) why << "inlier_threshold_px must be positive; ";
  if (!(confidence > 0.0 && confidence < 1.0)) why << "confidence must lie in (0, 1); ";
  if (max_iterations < 1) why << "max_iterations must be at least 1; ";
  if (max_refinements < 0) why << "max_refinements must not be negative; ";
  if (min_matches < 8) why << "min_matches must be at least 8; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

double EpipolarDistance(const cv::Matx33d& F, const cv::Point2f& previous, const cv::Point2f& current) {
  const cv::Vec3d p(previous.x, previous.y, 1.0), c(current.x, current.y, 1.0);
  const cv::Vec3d line_in_current = F * p;           // l' = F x
  const cv::Vec3d line_in_previous = F.t() * c;      // l = F^T x'
  const double e = c.dot(line_in_current);           // x'^T F x
  const double n1 = std::hypot(line_in_current[0], line_in_current[1]);
  const double n2 = std::hypot(line_in_previous[0], line_in_previous[1]);
  if (n1 < 1e-12 || n2 < 1e-12) return std::abs(e) > 1e-12 ? 1e12 : 0.0;
  return std::max(std::abs(e) / n1, std::abs(e) / n2);
}

std::optional<FundamentalResult> EstimateFundamental(const std::vector<cv::Point2f>& previous,
                                                     const std::vector<cv::Point2f>& current,
                                                     const FundamentalOptions& options) {
  if (previous.size() != current.size()) return std::nullopt;
  const int n = static_cast<int>(previous.size());
  if (n < options.min_matches) return std::nullopt;
  FundamentalResult result;
  cv::Mat mask;
  cv::Mat F = cv::findFundamentalMat(previous, current, cv::FM_RANSAC, options.inlier_threshold_px,
                                     options.confidence, options.max_iterations, mask);
  if (F.rows != 3 || F.cols != 3) return std::nullopt;  // none found (or several from 7 points)
  result.F = cv::Matx33d(F);
  result.inlier.assign(mask.ptr<unsigned char>(), mask.ptr<unsigned char>() + n);
  for (auto& m : result.inlier) m = m ? 1 : 0;
  result.inliers = static_cast<int>(std::count(result.inlier.begin(), result.inlier.end(), 1));
  if (result.inliers < 8) return std::nullopt;

  std::vector<cv::Point2f> in_prev, in_cur;
  std::vector<unsigned char> next(static_cast<std::size_t>(n));
  for (int round = 0; round < options.max_refinements; ++round) {
    in_prev.clear();
    in_cur.clear();
    for (int i = 0; i < n; ++i) {
      if (!result.inlier[static_cast<std::size_t>(i)]) continue;
      in_prev.push_back(previous[static_cast<std::size_t>(i)]);
      in_cur.push_back(current[static_cast<std::size_t>(i)]);
    }
    const cv::Mat refit = cv::findFundamentalMat(in_prev, in_cur, cv::FM_8POINT);  // step 3
    if (refit.rows != 3 || refit.cols != 3) break;
    const cv::Matx33d G(refit);
    int count = 0;
    for (int i = 0; i < n; ++i) {  // step 4
      const bool in = EpipolarDistance(G, previous[static_cast<std::size_t>(i)], current[static_cast<std::size_t>(i)]) <=
                      options.inlier_threshold_px;
      next[static_cast<std::size_t>(i)] = in ? 1 : 0;
      count += in ? 1 : 0;
    }
    if (count < 8) break;  // the refit collapsed: keep the last good estimate
    ++result.refinements;
    const bool stable = next == result.inlier;
    result.F = G;
    result.inlier = next;
    result.inliers = count;
    if (stable) break;
  }
  return result;
}

}  // namespace squint::obstacles
