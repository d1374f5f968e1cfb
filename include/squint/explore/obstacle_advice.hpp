// ObstacleAdvice from the obstacle pipeline's polar map and free-gap steering (issue 6): whether
// an occupied sector lies across the robot's path inside the region of interest, how far, and
// where the widest free gap is. The explorer's obstacle override consumes it (issue 7).
#pragma once

#include <string>

#include "squint/explore/percept.hpp"
#include "squint/obstacles/gap_steering.hpp"
#include "squint/obstacles/polar_map.hpp"

namespace squint::explore {

struct ObstacleAdviceOptions {
  // The robot's swept path straight ahead is 2 × (robot_radius_m + path_margin_m) wide; an occupied
  // sector is in the path when its nearest contact, placed on the sector's bearing nearest to
  // straight ahead, lies within that half-width of the robot's axis.
  double robot_radius_m = 0.25;  // the closed loop replaces it by the world's robot radius
  double path_margin_m = 0.10;

  std::string Validate() const;
};

// `decision` must come from the gaps of `map` (obstacles::FindGaps, ChooseSteering).
// obstacle_in_roi: any occupied sector; in_path / nearest_in_path_m: as above; blocked: the
// steering found no passable gap; steer_deg: the widest gap's centre (0 when blocked).
ObstacleAdvice MakeObstacleAdvice(const obstacles::PolarMap& map, const obstacles::SteeringDecision& decision,
                                  const ObstacleAdviceOptions& options);

}  // namespace squint::explore
