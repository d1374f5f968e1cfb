// Inverse perspective transformation through the camera model: floor points, discrepancy, horizon.
#include "squint/obstacles/ipt_geometry.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace squint::obstacles {

std::optional<Eigen::Vector2d> FloorPointWorld(const CameraModel& camera, const Pose2& world_T_robot,
                                               const Eigen::Vector2d& pixel) {
  const std::optional<Eigen::Vector2d> robot_point = camera.FloorPoint(pixel);
  if (!robot_point) return std::nullopt;
  return world_T_robot.Apply(*robot_point);
}

std::optional<double> Discrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                  const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                  const Eigen::Vector2d& current_pixel) {
  const auto a = FloorPointWorld(camera, world_T_previous, previous_pixel);
  const auto b = FloorPointWorld(camera, world_T_current, current_pixel);
  if (!a || !b) return std::nullopt;
  return (*b - *a).norm();
}

std::optional<double> SignedDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                        const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                        const Eigen::Vector2d& current_pixel) {
  const auto a = FloorPointWorld(camera, world_T_previous, previous_pixel);
  const auto b = FloorPointWorld(camera, world_T_current, current_pixel);
  if (!a || !b) return std::nullopt;
  // The optical centre lies above the robot's rotation centre (SEQUENCE_FORMAT.md).
  const Eigen::Vector2d camera_motion = world_T_current.Apply(camera.RobotCameraCentre().head<2>()) -
                                        world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  const double n = camera_motion.norm();
  if (n < 1e-12) return std::nullopt;
  return -(*b - *a).dot(camera_motion) / n;
}

std::optional<double> MirrorAwareDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                             const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                             const Eigen::Vector2d& current_pixel) {
  const auto a = FloorPointWorld(camera, world_T_previous, previous_pixel);
  const auto b = FloorPointWorld(camera, world_T_current, current_pixel);
  if (!a || !b) return std::nullopt;
  const Eigen::Vector2d camera_motion = world_T_current.Apply(camera.RobotCameraCentre().head<2>()) -
                                        world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  const double n2 = camera_motion.squaredNorm();
  if (n2 < 1e-24) return std::nullopt;
  const Eigen::Vector2d moved = *b - *a;
  const double k = std::clamp(moved.dot(camera_motion) / n2, 0.0, 1.0);
  return (moved - k * camera_motion).norm();
}

std::optional<Discrepancies> AllDiscrepancies(const CameraModel& camera, const Pose2& world_T_previous,
                                              const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                              const Eigen::Vector2d& current_pixel) {
  const auto a = FloorPointWorld(camera, world_T_previous, previous_pixel);
  const auto b = FloorPointWorld(camera, world_T_current, current_pixel);
  if (!a || !b) return std::nullopt;
  const Eigen::Vector2d camera_motion = world_T_current.Apply(camera.RobotCameraCentre().head<2>()) -
                                        world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  const double n2 = camera_motion.squaredNorm();
  if (n2 < 1e-24) return std::nullopt;
  const Eigen::Vector2d moved = *b - *a;
  const double along = moved.dot(camera_motion);
  const double k = std::clamp(along / n2, 0.0, 1.0);
  return Discrepancies{moved.norm(), -along / std::sqrt(n2), (moved - k * camera_motion).norm()};
}

namespace {
Eigen::Vector3d WorldRay(const CameraModel& camera, const Pose2& world_T_robot, const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d r = camera.PixelRayRobot(pixel);
  const double c = std::cos(world_T_robot.yaw), s = std::sin(world_T_robot.yaw);
  return {c * r.x() - s * r.y(), s * r.x() + c * r.y(), r.z()};
}
}  // namespace

std::optional<double> MotionEpipolarErrorPx(const CameraModel& camera, const Pose2& world_T_previous,
                                            const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                            const Eigen::Vector2d& current_pixel) {
  const Eigen::Vector2d c1 = world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  const Eigen::Vector2d c2 = world_T_current.Apply(camera.RobotCameraCentre().head<2>());
  const Eigen::Vector3d baseline(c2.x() - c1.x(), c2.y() - c1.y(), 0.0);
  if (baseline.norm() < 1e-12) return std::nullopt;
  const Eigen::Vector3d r1 = WorldRay(camera, world_T_previous, previous_pixel);
  const Eigen::Vector3d r2 = WorldRay(camera, world_T_current, current_pixel);
  // Angle of ray `a` out of the plane spanned by the baseline and ray `b`.
  auto out_of_plane = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d n = baseline.cross(b);
    const double norm = n.norm();
    if (norm < 1e-12 * baseline.norm()) return 0.0;
    return std::asin(std::min(1.0, std::abs(n.dot(a)) / norm));
  };
  return std::max(out_of_plane(r2, r1), out_of_plane(r1, r2)) * camera.fx;
}

bool AboveHorizon(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  return camera.PixelRayRobot(pixel).z() >= -1e-9;
}

}  // namespace squint::obstacles
