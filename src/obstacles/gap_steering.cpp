// Free-gap steering (obstacle paper §5.3).
#include "squint/obstacles/gap_steering.hpp"

#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string GapOptions::Validate() const {
  if (!(robot_radius_m > 0.0 && robot_radius_m <= 10.0)) return "gap.robot_radius_m must be in (0, 10]";
  if (!(margin_m >= 0.0 && margin_m <= 10.0)) return "gap.margin_m must be in [0, 10]";
  return {};
}

void FindGaps(const PolarMap& map, const GapOptions& options, std::vector<Gap>* gaps) {
  SQUINT_ENSURE(gaps != nullptr, "FindGaps needs an output vector");
  gaps->clear();
  const auto& s = map.sectors;
  const int n = static_cast<int>(s.size());
  const double required = options.RequiredWidthM();
  int i = 0;
  while (i < n) {
    if (s[i].state != SectorState::kFree) {
      ++i;
      continue;
    }
    int j = i;
    while (j + 1 < n && s[j + 1].state == SectorState::kFree) ++j;
    Gap g;
    g.first = i;
    g.last = j;
    g.start_deg = s[i].start_deg;
    g.end_deg = s[j].end_deg;
    g.centre_deg = 0.5 * (g.start_deg + g.end_deg);
    g.width_m = 2.0 * map.roi_radius_m;
    for (const PolarSector& o : s) {
      if (o.state != SectorState::kOccupied || !o.range_m) continue;
      // The occupied sector's edge nearest the ray (the contact may lie anywhere in the sector).
      const double edge = o.end_deg <= g.centre_deg ? o.end_deg : (o.start_deg >= g.centre_deg ? o.start_deg : g.centre_deg);
      const double off = DegToRad(std::abs(edge - g.centre_deg));
      if (off >= kPi / 2.0) continue;  // beside or behind the robot along this ray
      g.width_m = std::min(g.width_m, 2.0 * *o.range_m * std::sin(off));
    }
    g.passable = g.width_m >= required;
    gaps->push_back(g);
    i = j + 1;
  }
}

SteeringDecision ChooseSteering(const std::vector<Gap>& gaps) {
  SteeringDecision d;
  std::optional<int> best;
  for (int k = 0; k < static_cast<int>(gaps.size()); ++k) {
    const Gap& g = gaps[k];
    if (!g.passable) continue;
    if (!best) {
      best = k;
      continue;
    }
    const Gap& b = gaps[*best];
    const double wg = g.AngularWidthDeg(), wb = b.AngularWidthDeg();
    constexpr double kTieDeg = 1e-9;
    if (wg > wb + kTieDeg || (std::abs(wg - wb) <= kTieDeg && std::abs(g.centre_deg) < std::abs(b.centre_deg) - kTieDeg))
      best = k;
  }
  if (best) {
    d.stop = false;
    d.steer_deg = gaps[*best].centre_deg;
    d.gap = best;
  }
  return d;
}

bool StraightPathFree(std::span<const Eigen::Vector2d> points_m, double length_m, double half_width_m) {
  for (const Eigen::Vector2d& p : points_m) {
    if (p.x() < 0.0) continue;  // behind: moving forward only takes the robot away from it
    const double along = std::min(p.x(), length_m);
    if (std::hypot(p.x() - along, p.y()) < half_width_m) return false;
  }
  return true;
}

}  // namespace squint::obstacles
