// Planar robot poses (x forward, y left, yaw counter-clockwise; REP-103) and their algebra.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "squint/core/angles.hpp"

namespace squint {

// A rigid transform in the plane. Name variables by frames: world_T_robot maps robot
// coordinates into the world frame.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;  // radians

  // this ∘ other: a_T_c = a_T_b * b_T_c.
  Pose2 operator*(const Pose2& other) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * other.x - s * other.y, y + s * other.x + c * other.y, WrapPi(yaw + other.yaw)};
  }

  Pose2 Inverse() const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {-c * x - s * y, s * x - c * y, WrapPi(-yaw)};
  }

  Eigen::Vector2d Apply(const Eigen::Vector2d& p) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }

  Eigen::Vector2d Translation() const { return {x, y}; }
};

// The motion from a to b expressed in a's frame: a_T_b = world_T_a^-1 * world_T_b.
inline Pose2 Between(const Pose2& world_T_a, const Pose2& world_T_b) { return world_T_a.Inverse() * world_T_b; }

}  // namespace squint
