// Free-gap steering on the polar occupancy map (obstacle paper §5.3): runs of free sectors are
// gaps; gaps narrower than the robot are excluded; steer to the centre of the widest remaining
// gap, or stop when there is none.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "squint/obstacles/polar_map.hpp"

namespace squint::obstacles {

struct GapOptions {
  double robot_radius_m = 0.25;  // a Pioneer 3-DX is about 0.5 m wide
  double margin_m = 0.05;        // clearance on each side
  // A gap passes when its width is at least 2 * (robot_radius_m + margin_m).
  double RequiredWidthM() const { return 2.0 * (robot_radius_m + margin_m); }

  std::string Validate() const;
};

// A maximal run of free sectors [first, last] (unseen sectors end a run: squint steers only
// toward floor it has seen).
struct Gap {
  int first = 0;
  int last = 0;
  double start_deg = 0.0;  // right edge
  double end_deg = 0.0;    // left edge
  double centre_deg = 0.0;
  // Twice the clearance of the ray through the gap's centre: the smallest lateral distance from
  // that ray to the nearest contact of any occupied sector ahead of the robot, each placed on its
  // sector's edge nearest the ray; 2 * roi_radius_m when nothing is near. For a gap between two
  // contacts at the same range r this is the chord 2 r sin(angle / 2). Unseen sectors hold no
  // contacts and do not narrow a gap.
  double width_m = 0.0;
  bool passable = false;
  double AngularWidthDeg() const { return end_deg - start_deg; }
};

struct SteeringDecision {
  std::optional<double> steer_deg;  // left positive; none when stopping
  bool stop = true;
  std::optional<int> gap;  // index into the gaps the decision came from
};

// Finds the gaps of `map` into `gaps` (cleared first; its capacity is reused).
void FindGaps(const PolarMap& map, const GapOptions& options, std::vector<Gap>* gaps);

// The centre of the widest passable gap (by angle; ties go to the one nearer straight ahead,
// then to the rightmost); stop when no gap is passable.
SteeringDecision ChooseSteering(const std::vector<Gap>& gaps);

// Whether a disc of radius `half_width_m` centred on the robot (origin, heading +x) can move
// `length_m` straight ahead without any of `points_m` (robot frame) coming within the disc: no
// point lies within `half_width_m` of the segment from (0, 0) to (length_m, 0). Points behind
// the robot (x < 0) never block it.
bool StraightPathFree(std::span<const Eigen::Vector2d> points_m, double length_m, double half_width_m);

}  // namespace squint::obstacles
