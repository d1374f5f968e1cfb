// Obstacle-to-floor contact points in the robot frame: range and bearing (obstacle paper eq. 16,
// in general form through the camera model's floor back-projection).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "squint/core/camera.hpp"

namespace squint::obstacles {

// A contact point relative to the robot (origin on the floor under the rotation centre, which is
// under the camera; x forward, y left). The paper's eq. 16 measures the angle with arccos and
// calls turns to the right positive; here bearings are counter-clockwise (left) positive, as
// everywhere in squint: bearing_deg = atan2(y, x).
struct ContactPoint {
  Eigen::Vector2d pixel;     // (u, v) in the image
  Eigen::Vector2d floor_m;   // (x, y) on the floor, robot frame
  double range_m = 0.0;      // dcp: distance from the robot (camera foot) to the point
  double bearing_deg = 0.0;  // left positive
};

// Back-projects a contact pixel onto the floor; none when its ray does not meet the floor (at
// or above the horizon), since such a pixel cannot be where something stands on the floor.
std::optional<ContactPoint> ContactFromPixel(const CameraModel& camera, const Eigen::Vector2d& pixel);

}  // namespace squint::obstacles
