// Unicycle robot with collision stops, and the wheel-odometry noise model.
#include "squint/sim/robot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::sim {

std::string OdometryOptions::Validate() const {
  std::ostringstream why;
  if (!(trans_noise_frac >= 0) || !(rot_noise_frac >= 0)) why << "odometry noise fractions must not be negative; ";
  if (!std::isfinite(drift_rad_per_m)) why << "drift_rad_per_m must be finite; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

std::string RobotOptions::Validate() const {
  std::string s = odometry.Validate();
  if (!(step_s > 0)) s += std::string(s.empty() ? "" : "; ") + "step_s must be positive";
  if (substeps < 1) s += std::string(s.empty() ? "" : "; ") + "substeps must be at least 1";
  return s;
}

Odometry::Odometry(const OdometryOptions& options) : options_(options), rng_(options.seed) {
  const std::string why = options.Validate();
  SQUINT_ENSURE(why.empty(), why);
}

void Odometry::Reset(const Pose2& world_T_robot) {
  last_true_ = world_T_robot;
  odom_T_robot_ = Pose2{};
  started_ = true;
  rng_.seed(options_.seed);
}

Pose2 Odometry::Update(const Pose2& world_T_robot) {
  if (!started_) {
    Reset(world_T_robot);
    return odom_T_robot_;
  }
  const Pose2 delta = Between(last_true_, world_T_robot);
  last_true_ = world_T_robot;
  const double trans = std::hypot(delta.x, delta.y);
  const double rot = std::abs(delta.yaw);
  std::normal_distribution<double> n(0.0, 1.0);
  // Per-increment errors proportional to the motion (so they vanish when standing still).
  const double scale = 1.0 + options_.trans_noise_frac * n(rng_);
  const double dyaw = delta.yaw * (1.0 + options_.rot_noise_frac * n(rng_)) + options_.drift_rad_per_m * trans +
                      options_.rot_noise_frac * 0.1 * trans * n(rng_);
  (void)rot;
  odom_T_robot_ = odom_T_robot_ * Pose2{delta.x * scale, delta.y * scale, dyaw};
  return odom_T_robot_;
}

Robot::Robot(const World& world, const Pose2& start, const RobotOptions& options)
    : world_(&world), options_(options), pose_(start), odometry_(options.odometry) {
  const std::string why = options.Validate();
  if (!why.empty()) throw Error("robot options: " + why);
  if (!IsFreePose(start.Translation()))
    throw Error(fmt::format("{}: the robot (radius {:.2f} m) does not fit at ({:.2f}, {:.2f})", world.source,
                            world.robot.radius_m, start.x, start.y));
  odometry_.Reset(start);
}

bool Robot::IsFreePose(const Eigen::Vector2d& p) const {
  const double r = world_->robot.radius_m;
  return world_->IsFree(p) && world_->DistanceToWalls(p) >= r && world_->DistanceToObstacles(p) >= r;
}

StepResult Robot::Step(double v_mps, double omega_rps) {
  StepResult result;
  const double vmax = world_->robot.max_speed_mps, wmax = DegToRad(world_->robot.max_turn_rate_dps);
  const double v = std::clamp(std::isfinite(v_mps) ? v_mps : 0.0, -vmax, vmax);
  const double w = std::clamp(std::isfinite(omega_rps) ? omega_rps : 0.0, -wmax, wmax);
  const double dt = options_.step_s / options_.substeps;
  for (int i = 0; i < options_.substeps; ++i) {
    Pose2 next = pose_;
    // Exact unicycle arc over dt.
    if (std::abs(w) < 1e-9) {
      next.x += v * dt * std::cos(pose_.yaw);
      next.y += v * dt * std::sin(pose_.yaw);
    } else {
      const double r = v / w;
      next.x += r * (std::sin(pose_.yaw + w * dt) - std::sin(pose_.yaw));
      next.y -= r * (std::cos(pose_.yaw + w * dt) - std::cos(pose_.yaw));
    }
    next.yaw = WrapPi(pose_.yaw + w * dt);
    if (v != 0.0 && !IsFreePose(next.Translation())) {
      result.collided = true;
      const Eigen::Vector2d p = next.Translation();
      const double r = world_->robot.radius_m;
      const auto [d_obs, i_obs] = world_->NearestObstacle(p);
      result.hit = d_obs < r ? world_->obstacles[i_obs].source : "wall";
      ++collisions_;
      break;
    }
    travelled_m_ += std::abs(v) * dt;
    pose_ = next;
  }
  time_s_ += options_.step_s;
  odometry_.Update(pose_);
  return result;
}

}  // namespace squint::sim
