// Per-frame ground truth (SEQUENCE_FORMAT.md): heading relative to the current corridor's axis,
// lateral offset from its centre line, and distance to the corridor's end wall.
#pragma once

#include <optional>

#include "squint/core/ground_truth.hpp"
#include "squint/core/pose.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {

struct CorridorFrame {
  int corridor = -1;                 // index into World::corridors
  Eigen::Vector2d axis_dir;          // the axis direction the robot faces (from->to or back)
  double heading_rad = 0.0;          // robot yaw minus axis direction, wrapped, left positive
  double lateral_m = 0.0;            // signed offset from the centre line, left of axis_dir positive
  double along_m = 0.0;              // position along axis_dir from the corridor's `from`/`to` start
};

// The corridor the robot is in: among the corridors whose floor contains the position, the one
// whose axis is closest to the robot's heading (so at a junction it is the one it drives along).
std::optional<CorridorFrame> CurrentCorridor(const World& world, const Pose2& world_T_robot);

// Ground truth for a robot pose (the camera is at the robot's rotation centre). dist_end_m is
// measured along the axis from the camera's projection on the centre line to the first wall the
// centre line meets (a dead end, or the far wall of a T or L junction; a cross junction or a
// collinear continuation is passed through). All empty outside the floor area.
GroundTruth GroundTruthAt(const World& world, const Pose2& world_T_robot);

}  // namespace squint::sim
