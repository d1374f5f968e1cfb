// What the explorer sees each frame (camera-derived estimates plus wheel odometry) and what it
// commands. Nothing here comes from a simulator's ground truth: the explorer is blind to it.
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include "squint/core/pose.hpp"
#include "squint/explore/visual_sonar.hpp"

namespace squint::explore {

// Advice of the obstacle pipeline (issue 6's polar map and free-gap steering), when it runs
// (explore/obstacle_advice.hpp builds it). Bearings relative to the robot's heading at the frame.
struct ObstacleAdvice {
  bool obstacle_in_roi = false;  // some sector of the region of interest is occupied
  bool in_path = false;          // an occupied sector lies across the robot's path straight ahead
  double nearest_in_path_m = std::numeric_limits<double>::infinity();  // distance ahead to it
  bool blocked = false;          // no free gap wide enough for the robot
  double steer_deg = 0.0;        // centre of the widest free gap, left positive (0 when blocked)
};

// One camera frame's worth of perception, as the explorer consumes it. All estimates come from
// the 32×24 glance (corridor module) and the odometry from the wheels.
struct Percept {
  double stamp_s = 0.0;
  Pose2 odom_T_robot;  // wheel odometry (drifts; the explorer corrects its yaw by vision)
  // True when the rapid-perception gate let the frame through to full processing; when false
  // the estimates below are empty and the explorer propagates the last ones by odometry.
  bool processed = false;
  std::optional<double> heading_deg;         // fused heading relative to the corridor axis
  // The Perceiver's heading filter over time (odometry turn as the process, HeadingFilterOptions),
  // when the caller runs it; used by ExplorerOptions::filtered_axis_gain. heading_deg is then the
  // per-frame fusion.
  std::optional<double> heading_filtered_deg;
  std::optional<double> centre_heading_deg;  // translation-sensitive cues (bright pixels, symmetry)
  std::optional<double> dist_end_m;          // fused distance to the corridor's end
  // The ceiling lights' line in the glance (light_line.hpp), when one was found this frame: the
  // robot's lateral position from it (metres at the nominal light height, left positive) and the
  // robot's heading relative to it (degrees, left positive).
  std::optional<double> light_lateral_m;
  std::optional<double> light_heading_deg;
  // The walls' base lines where the floor's texture ends (wall_lines.hpp), when a frame for them
  // was taken and they were found: the robot's heading relative to them, modulo 90° in
  // [−45°, 45°) (degrees, left positive).
  std::optional<double> wall_line_heading_deg;
  // ...and, when both walls' lines were found with the robot between them, how far ahead they
  // show the corridor free (WallLines::corridor_ahead_m, metres).
  std::optional<double> wall_line_corridor_ahead_m;
  // ...and, when they were found (not in the heading-only frames of a standstill), the main line's
  // direction in the robot frame (WallLines::direction_rad, degrees in (−90, 90], left positive)
  // and its signed distance along its left normal (WallLines::offset_m), and the parallel line's
  // (WallLines::parallel_offset_m) when at least WallLineOptions::min_inliers / 2 points lie on it.
  std::optional<double> wall_line_direction_deg;
  std::optional<double> wall_line_offset_m;
  std::optional<double> wall_line_parallel_offset_m;
  // ...and, whenever a frame for them was taken, each of its columns' texture at the frame's
  // bottom (WallLines::bottom_texture, left to right across the camera's view); valid during Step() only.
  const std::vector<float>* wall_bottom_texture = nullptr;
  // Whole-glance grey-level entropy (nats); the gate computes it on every frame, processed or not.
  std::optional<double> glance_entropy_nats;
  std::optional<ObstacleAdvice> obstacles;   // empty when the obstacle pipeline is off
  // The visual sonar's scan of this frame (range per bearing from the floor boundary of a small
  // camera frame), when one was taken (a sub-rate); valid during Step() only.
  const std::vector<SonarColumn>* sonar = nullptr;
  double sonar_near_blind_m = 0.0;  // the sonar's blind range (nothing nearer is seen)
  double sonar_wall_lines = 0.0;    // the sonar frame's fraction of bands with periodic horizontal lines (brick)
  // The sonar frame's grey level per column above the horizon (VisualSonar::HorizonProfile), with
  // the scan; valid during Step() only.
  const std::vector<float>* sonar_profile = nullptr;
};

// Unicycle velocity command.
struct Command {
  double v_mps = 0.0;
  double omega_rps = 0.0;  // counter-clockwise positive
};

}  // namespace squint::explore
