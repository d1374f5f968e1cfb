// Ground truth per pose: the current corridor (the containing corridor best aligned with the
// heading), heading and lateral offset relative to its axis, and the distance along the centre
// line to the first wall ahead.
#include "squint/sim/ground_truth.hpp"

#include <cmath>

#include "squint/core/angles.hpp"

namespace squint::sim {

std::optional<CorridorFrame> CurrentCorridor(const World& world, const Pose2& world_T_robot) {
  const Eigen::Vector2d p = world_T_robot.Translation();
  std::optional<CorridorFrame> best;
  for (std::size_t i = 0; i < world.corridors.size(); ++i) {
    const Corridor& c = world.corridors[i];
    if (!c.rect.Contains(p, 1e-9)) continue;
    const Eigen::Vector2d ax = c.Axis();
    for (int sign = 1; sign >= -1; sign -= 2) {
      const Eigen::Vector2d dir = ax * sign;
      const double heading = AngleDiff(world_T_robot.yaw, std::atan2(dir.y(), dir.x()));
      if (best && std::abs(heading) >= std::abs(best->heading_rad) - 1e-12) continue;
      CorridorFrame f;
      f.corridor = static_cast<int>(i);
      f.axis_dir = dir;
      f.heading_rad = heading;
      const Eigen::Vector2d left(-dir.y(), dir.x());
      const Eigen::Vector2d start = sign > 0 ? c.from : c.to;
      f.lateral_m = (p - start).dot(left);
      f.along_m = (p - start).dot(dir);
      best = f;
    }
  }
  return best;
}

GroundTruth GroundTruthAt(const World& world, const Pose2& world_T_robot) {
  GroundTruth gt;
  const auto f = CurrentCorridor(world, world_T_robot);
  if (!f) return gt;
  gt.heading_deg = RadToDeg(f->heading_rad);
  gt.lateral_m = f->lateral_m;
  // Cast along the centre line from the camera's projection onto it.
  const Eigen::Vector2d left(-f->axis_dir.y(), f->axis_dir.x());
  const Eigen::Vector2d q = world_T_robot.Translation() - left * f->lateral_m;
  if (const auto hit = world.CastWalls(q, f->axis_dir)) gt.dist_end_m = hit->first;
  return gt;
}

}  // namespace squint::sim
