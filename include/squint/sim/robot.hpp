// The simulated robot: unicycle kinematics at a fixed step, collisions with walls and obstacles,
// and wheel odometry with configurable noise and drift.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include "squint/core/pose.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {

struct OdometryOptions {
  double trans_noise_frac = 0.01;    // std-dev of distance error per metre travelled (fraction)
  double rot_noise_frac = 0.02;      // std-dev of yaw error per radian turned (fraction)
  double drift_rad_per_m = 0.002;    // systematic yaw drift per metre travelled (left positive)
  std::uint64_t seed = 7;
  std::string Validate() const;
};

// Integrates the true motion between successive poses into a noisy odometry pose (starts at
// the identity at the first pose, REP-103 odometry frame: x forward at the start).
class Odometry {
 public:
  explicit Odometry(const OdometryOptions& options = {});
  void Reset(const Pose2& world_T_robot);
  // Feeds the next true pose; returns odom_T_robot.
  Pose2 Update(const Pose2& world_T_robot);
  const Pose2& Pose() const { return odom_T_robot_; }

 private:
  OdometryOptions options_;
  std::mt19937_64 rng_;
  Pose2 last_true_;
  Pose2 odom_T_robot_;
  bool started_ = false;
};

struct RobotOptions {
  double step_s = 1.0 / 30.0;  // integration step of Step()
  int substeps = 4;            // collision checks per step
  OdometryOptions odometry;
  std::string Validate() const;
};

struct StepResult {
  bool collided = false;   // this step would have hit a wall or obstacle: the robot stopped
  std::string hit;         // what it hit: "wall" or the obstacle's entry, empty otherwise
};

class Robot {
 public:
  // Throws squint::Error when `start` is not a free pose for the robot's disc.
  Robot(const World& world, const Pose2& start, const RobotOptions& options = {});

  // Applies (v, omega), clipped to the world's speed limits, for one step. On a collision the
  // robot stays at its last free pose (its velocity is lost) and the collision is counted.
  StepResult Step(double v_mps, double omega_rps);

  const Pose2& TruePose() const { return pose_; }
  const Pose2& OdomPose() const { return odometry_.Pose(); }
  double Time() const { return time_s_; }
  double DistanceTravelled() const { return travelled_m_; }
  int Collisions() const { return collisions_; }
  // True when the disc of the robot's radius at p touches no wall and no obstacle.
  bool IsFreePose(const Eigen::Vector2d& p) const;

 private:
  const World* world_;
  RobotOptions options_;
  Pose2 pose_;
  Odometry odometry_;
  double time_s_ = 0.0;
  double travelled_m_ = 0.0;
  int collisions_ = 0;
};

}  // namespace squint::sim
