// The papers' recording protocols as pose schedules: the exploration paper's rotate-in-place
// sweeps (§5.1) and drives down the corridor (§5.2), and the obstacle paper's creep (§6).
#pragma once

#include <string>
#include <vector>

#include "squint/core/pose.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {

struct TimedPose {
  double stamp = 0.0;
  Pose2 pose;  // true world_T_robot
};

struct SweepOptions {
  double spacing_m = 4.572;      // 15 ft between sweep stations
  double min_deg = -20.0, max_deg = 20.0, step_deg = 1.0;
  double rate_hz = 0.5;          // one frame per 2 s (2 deg/s)
  double end_margin_m = 1.5;     // no station closer than this to either end wall
  int corridor = 0;              // which corridor of the world
  std::string Validate() const;
};

struct DriveOptions {
  std::vector<double> lateral_m = {0.0, 0.45, -0.45};  // one pass per offset, left positive
  double speed_mps = 0.4;
  double rate_hz = 30.0;
  double start_margin_m = 1.0;   // start this far from the `from` end wall
  double stop_dist_m = 0.5;      // stop when the camera is this far from the end wall
  int corridor = 0;
  std::string Validate() const;
};

struct CreepOptions {
  double step_m = 0.031;         // 40 mm/s over 0.77 s between frames
  double period_s = 0.77;
  double clearance_m = 0.15;     // extra clearance kept from obstacles by the planned path
  double stop_dist_m = 1.0;      // stop this far before the end wall
  int corridor = 0;
  std::string Validate() const;
};

// Pose schedules; each throws squint::Error (naming the world) when the corridor is too short or
// the path is blocked.
std::vector<TimedPose> SweepSchedule(const World& world, const SweepOptions& options);
std::vector<TimedPose> DriveSchedule(const World& world, const DriveOptions& options);
std::vector<TimedPose> CreepSchedule(const World& world, const CreepOptions& options);

}  // namespace squint::sim
