// Drawing a world's floor plan (walls, lights, obstacles, flat items, doors) as a BGR image,
// with the world-to-pixel mapping so that callers can draw paths on it.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "squint/core/pose.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {

struct FloorPlanOptions {
  double px_per_m = 20.0;
  double margin_m = 1.0;
  bool draw_lights = true;
  bool draw_centre_lines = true;
};

class FloorPlan {
 public:
  FloorPlan(const World& world, const FloorPlanOptions& options = {});
  cv::Mat& Image() { return image_; }
  const cv::Mat& Image() const { return image_; }
  // World metres -> image pixel (y up in the world is up in the image).
  cv::Point2d ToPixel(const Eigen::Vector2d& world_xy) const;
  void DrawPath(const std::vector<Pose2>& poses, const cv::Scalar& bgr, int thickness = 1);
  void DrawRobot(const Pose2& pose, double radius_m, const cv::Scalar& bgr);

 private:
  FloorPlanOptions options_;
  Box2 bounds_;
  cv::Mat image_;
};

}  // namespace squint::sim
