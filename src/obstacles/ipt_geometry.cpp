// Inverse perspective transformation through the camera model: floor points, discrepancy, horizon.
#include "squint/obstacles/ipt_geometry.hpp"

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

bool AboveHorizon(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  return camera.PixelRayRobot(pixel).z() >= -1e-9;
}

}  // namespace squint::obstacles
