// Test helper: ray-cast images of boxes standing on a flat floor, seen by the obstacle data sets'
// camera (obstacle_camera.hpp), with the analytic answers (contact pixels, ranges, bearings).
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "obstacle_camera.hpp"
#include "squint/core/camera.hpp"
#include "squint/obstacles/feature.hpp"

namespace squint::obstacles::testing {

// An axis-aligned box on the floor: x in [x_near, x_far], y in [y_right, y_left], z in [0, h].
struct Box {
  double x_near_m, x_far_m, y_right_m, y_left_m, height_m;
  std::uint8_t grey = 40;
};

// Ray-casts the scene: floor (grey `floor_grey`), background above the horizon, and boxes.
inline cv::Mat RenderBoxes(const CameraModel& cam, const std::vector<Box>& boxes, std::uint8_t floor_grey = 150,
                           std::uint8_t sky_grey = 150) {
  cv::Mat img(cam.height, cam.width, CV_8U, cv::Scalar(sky_grey));
  const Eigen::Vector3d o = cam.RobotCameraCentre();
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d d = cam.PixelRayRobot(Eigen::Vector2d(u, v));
      double best_t = 1e9;
      std::uint8_t grey = sky_grey;
      if (d.z() < 0) {
        best_t = o.z() / -d.z();
        grey = floor_grey;
      }
      for (const Box& b : boxes) {
        // Slab intersection.
        double t0 = 0, t1 = 1e9;
        const double lo[3] = {b.x_near_m, b.y_right_m, 0.0}, hi[3] = {b.x_far_m, b.y_left_m, b.height_m};
        bool hit = true;
        for (int k = 0; k < 3 && hit; ++k) {
          if (std::abs(d[k]) < 1e-12) {
            if (o[k] < lo[k] || o[k] > hi[k]) hit = false;
            continue;
          }
          double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          if (t0 > t1) hit = false;
        }
        if (hit && t0 < best_t) {
          best_t = t0;
          grey = b.grey;
        }
      }
      img.at<std::uint8_t>(v, u) = grey;
    }
  }
  return img;
}

inline ClassifiedFeature Feature(const CameraModel& cam, const Eigen::Vector3d& robot_point, FeatureClass cls) {
  ClassifiedFeature f;
  f.pixel = *cam.Project(robot_point);
  f.previous_pixel = f.pixel;
  f.cls = cls;
  return f;
}

}  // namespace squint::obstacles::testing
