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

namespace {

// The three discrepancies from the two floor points (world frame) and the camera centre's motion.
std::optional<Discrepancies> DiscrepanciesFrom(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                               const Eigen::Vector2d& camera_motion) {
  const double n2 = camera_motion.squaredNorm();
  if (n2 < 1e-24) return std::nullopt;
  const Eigen::Vector2d moved = b - a;
  const double along = moved.dot(camera_motion);
  const double k = std::clamp(along / n2, 0.0, 1.0);
  return Discrepancies{moved.norm(), -along / std::sqrt(n2), (moved - k * camera_motion).norm()};
}

// A robot-frame ray turned by the yaw (cosine c, sine s) into the world.
Eigen::Vector3d WorldRayFrom(double c, double s, const Eigen::Vector3d& r) {
  return {c * r.x() - s * r.y(), s * r.x() + c * r.y(), r.z()};
}

// MotionEpipolarErrorPx from the two camera centres and the two world rays.
std::optional<double> EpipolarFrom(const CameraModel& camera, const Eigen::Vector2d& c1, const Eigen::Vector2d& c2,
                                   const Eigen::Vector3d& r1, const Eigen::Vector3d& r2) {
  const Eigen::Vector3d baseline(c2.x() - c1.x(), c2.y() - c1.y(), 0.0);
  if (baseline.norm() < 1e-12) return std::nullopt;
  // Angle of ray `a` out of the plane spanned by the baseline and ray `b`.
  auto out_of_plane = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d n = baseline.cross(b);
    const double norm = n.norm();
    if (norm < 1e-12 * baseline.norm()) return 0.0;
    return std::asin(std::min(1.0, std::abs(n.dot(a)) / norm));
  };
  return std::max(out_of_plane(r2, r1), out_of_plane(r1, r2)) * camera.fx;
}

}  // namespace

std::optional<Discrepancies> AllDiscrepancies(const CameraModel& camera, const Pose2& world_T_previous,
                                              const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                              const Eigen::Vector2d& current_pixel) {
  const auto a = FloorPointWorld(camera, world_T_previous, previous_pixel);
  const auto b = FloorPointWorld(camera, world_T_current, current_pixel);
  if (!a || !b) return std::nullopt;
  // The optical centre lies above the robot's rotation centre (SEQUENCE_FORMAT.md).
  const Eigen::Vector2d camera_motion = world_T_current.Apply(camera.RobotCameraCentre().head<2>()) -
                                        world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  return DiscrepanciesFrom(*a, *b, camera_motion);
}

std::optional<double> SignedDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                        const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                        const Eigen::Vector2d& current_pixel) {
  const auto d = AllDiscrepancies(camera, world_T_previous, previous_pixel, world_T_current, current_pixel);
  if (!d) return std::nullopt;
  return d->signed_m;
}

std::optional<double> MirrorAwareDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                             const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                             const Eigen::Vector2d& current_pixel) {
  const auto d = AllDiscrepancies(camera, world_T_previous, previous_pixel, world_T_current, current_pixel);
  if (!d) return std::nullopt;
  return d->mirror_aware_m;
}

std::optional<double> MotionEpipolarErrorPx(const CameraModel& camera, const Pose2& world_T_previous,
                                            const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                            const Eigen::Vector2d& current_pixel) {
  const Eigen::Vector2d c1 = world_T_previous.Apply(camera.RobotCameraCentre().head<2>());
  const Eigen::Vector2d c2 = world_T_current.Apply(camera.RobotCameraCentre().head<2>());
  const Eigen::Vector3d r1 = WorldRayFrom(std::cos(world_T_previous.yaw), std::sin(world_T_previous.yaw),
                                          camera.PixelRayRobot(previous_pixel));
  const Eigen::Vector3d r2 = WorldRayFrom(std::cos(world_T_current.yaw), std::sin(world_T_current.yaw),
                                          camera.PixelRayRobot(current_pixel));
  return EpipolarFrom(camera, c1, c2, r1, r2);
}

PairGeometry::PairGeometry(const CameraModel& camera, const Pose2& world_T_previous, const Pose2& world_T_current)
    : camera_(camera),
      previous_{world_T_previous.x, world_T_previous.y, std::cos(world_T_previous.yaw), std::sin(world_T_previous.yaw)},
      current_{world_T_current.x, world_T_current.y, std::cos(world_T_current.yaw), std::sin(world_T_current.yaw)},
      centre_previous_(previous_.Apply(camera.RobotCameraCentre().head<2>())),
      centre_current_(current_.Apply(camera.RobotCameraCentre().head<2>())) {}

FeatureMeasures PairGeometry::Measure(const Eigen::Vector2d& previous_pixel, const Eigen::Vector2d& current_pixel) const {
  FeatureMeasures m;
  const Eigen::Vector3d ray_previous = camera_.PixelRayRobot(previous_pixel);
  const Eigen::Vector3d ray_current = camera_.PixelRayRobot(current_pixel);
  m.motion_epipolar_px = EpipolarFrom(camera_, centre_previous_, centre_current_,
                                      WorldRayFrom(previous_.c, previous_.s, ray_previous),
                                      WorldRayFrom(current_.c, current_.s, ray_current));
  m.above_horizon = ray_current.z() >= -1e-9;
  if (!m.above_horizon) {
    const auto a = camera_.FloorPointOfRay(ray_previous);
    const auto b = camera_.FloorPointOfRay(ray_current);
    if (a && b)
      m.discrepancies = DiscrepanciesFrom(previous_.Apply(*a), current_.Apply(*b), centre_current_ - centre_previous_);
  }
  return m;
}

bool AboveHorizon(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  return camera.PixelRayRobot(pixel).z() >= -1e-9;
}

}  // namespace squint::obstacles
