// Vertical edges ranged by motion parallax: a near corner the visual sonar cannot range.
//
// The visual sonar ranges what stands on the floor by where its base meets the floor, so inside
// the camera's blind range (no floor in view: 1.28 m for corridor-9's camera) it knows only that
// something is there, not how near. A wall's vertical edge seen through the camera's height shows
// as a step in grey level between neighbouring columns of the frame's rows above the horizon
// (VisualSonar::HorizonProfile). Turning in place moves every edge by the turn alone (the camera
// turns about its own foot); driving moves an edge by an angle that grows as it comes nearer. Two
// frames (the latest and one of the last `history` frames taken min_baseline_m to
// max_baseline_m from it, facing within max_turn_rad of it), with the same edge found in both
// (the same sign of step and the grey levels on each side within level_tolerance, the only such
// edge within match_window_rad of the bearing the second frame predicts for a far edge), give
// the edge's position by intersecting the two rays. Edges ranged
// between min_range_m and max_range_m, even with the angle the edge moved through reduced by
// angle_noise_rad, and alike (agree_fraction) when paired with the oldest and with the newest
// such kept frame, are returned as points in the odometry frame.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "squint/core/pose.hpp"

namespace squint::explore {

struct NearEdgeOptions {
  double min_step = 12.0;          // grey levels between neighbouring columns of the profile
  double level_tolerance = 12.0;   // each side's grey level in the two frames
  double min_baseline_m = 0.04;    // the frames' odometry positions at least this far apart...
  double max_baseline_m = 0.3;     // ...and at most this far
  double max_turn_rad = 0.35;      // ...facing within this of each other (about 20 degrees)
  int history = 10;                // frames kept
  double agree_fraction = 0.25;    // the two pairs' ranges within this fraction of the larger
  double match_window_rad = 0.08;  // how far from a far edge's predicted bearing a match may lie
  double min_range_m = 0.1;
  double max_range_m = 0.9;
  double min_off_axis_rad = 0.09;  // edges this near the line of travel give no parallax (about 5 degrees)
  // An edge's bearing is known to about this (sub-column, noise): an edge counts only where its
  // range stays within max_range_m with the angle it moved through reduced by this.
  double angle_noise_rad = 0.0087;
  int border_columns = 2;          // edges this near the frame's sides may be cut by it
  std::string Validate() const;    // empty when valid
};

struct NearEdge {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  // odometry frame
  double range_m = 0.0;    // from the second frame's position
  double bearing_rad = 0.0;  // in the second frame, left positive
  double column = 0.0;       // in the second frame, in columns (a fraction between two)
};

class NearEdgeRanger {
 public:
  explicit NearEdgeRanger(const NearEdgeOptions& options = {});

  // One frame: `profile` the grey level per column (HorizonProfile), `bearings` each column's
  // bearing (left positive, the same length), taken at `odom_T_robot`. Returns the edges ranged
  // alike against the oldest and the newest kept frames that qualify (empty when fewer than two
  // do); the frame is then kept. Throws std::logic_error (SQUINT_ENSURE) when the sizes differ
  // or are below 4 columns.
  const std::vector<NearEdge>& Process(const std::vector<float>& profile, const std::vector<double>& bearings,
                                       const Pose2& odom_T_robot);
  // Forgets the kept frames.
  void Reset() { history_.clear(); }

 private:
  struct Edge {
    double bearing = 0.0;  // robot frame
    double column = 0.0;
    int sign = 0;
    float left = 0.0f, right = 0.0f;  // grey levels on each side
  };
  struct Frame {
    Pose2 pose;
    std::vector<Edge> edges;
  };
  void FindEdges(const std::vector<float>& profile, const std::vector<double>& bearings, std::vector<Edge>* out) const;
  // The range of edge e of the frame taken at `pose`, paired with its match in `ref`; < 0 when it
  // has none (no unique match, too little parallax, out of range).
  double Range(const Edge& e, const Pose2& pose, const Frame& ref) const;

  NearEdgeOptions options_;
  std::deque<Frame> history_;  // oldest first
  std::vector<Edge> cur_;
  std::vector<NearEdge> out_;
};

}  // namespace squint::explore
