// Turns the obstacle pipeline's polar map and steering decision into the explorer's ObstacleAdvice.
#include "squint/explore/obstacle_advice.hpp"

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::explore {

std::string ObstacleAdviceOptions::Validate() const {
  if (!(std::isfinite(robot_radius_m) && robot_radius_m > 0.0)) return "robot_radius_m must be positive";
  if (!(std::isfinite(path_margin_m) && path_margin_m >= 0.0)) return "path_margin_m must be >= 0";
  return {};
}

ObstacleAdvice MakeObstacleAdvice(const obstacles::PolarMap& map, const obstacles::SteeringDecision& decision,
                                  const ObstacleAdviceOptions& options) {
  const std::string err = options.Validate();
  SQUINT_ENSURE(err.empty(), "ObstacleAdviceOptions: " + err);
  const double half_width = options.robot_radius_m + options.path_margin_m;
  ObstacleAdvice a;
  for (const obstacles::PolarSector& s : map.sectors) {
    if (s.state != obstacles::SectorState::kOccupied || !s.range_m) continue;
    a.obstacle_in_roi = true;
    // The bearing of the sector nearest to straight ahead (0 when the sector spans it).
    const double b_deg = s.start_deg <= 0.0 && s.end_deg >= 0.0 ? 0.0
                         : s.start_deg > 0.0                     ? s.start_deg
                                                                 : s.end_deg;
    const double b = DegToRad(b_deg);
    const double lateral = *s.range_m * std::abs(std::sin(b));
    const double ahead = *s.range_m * std::cos(b);
    if (lateral > half_width || ahead <= 0.0) continue;
    a.in_path = true;
    a.nearest_in_path_m = std::min(a.nearest_in_path_m, ahead);
  }
  a.blocked = decision.stop || !decision.steer_deg;
  a.steer_deg = a.blocked ? 0.0 : *decision.steer_deg;
  return a;
}

}  // namespace squint::explore
