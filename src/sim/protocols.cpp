// Pose schedules for the papers' protocols: sweeps (exploration paper §5.1), drives (§5.2) and
// the obstacle paper's creep (§6), the latter planned around the obstacles on a grid (A*).
#include "squint/sim/protocols.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/sim/ground_truth.hpp"

namespace squint::sim {
namespace {

std::string Join(std::ostringstream& why) {
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

const Corridor& Pick(const World& world, int index, const char* what) {
  if (index < 0 || index >= static_cast<int>(world.corridors.size()))
    throw Error(fmt::format("{}: {}: corridor index {} out of range (the world has {})", world.source, what, index,
                            world.corridors.size()));
  return world.corridors[index];
}

// Along-axis free span of a corridor's centre line: from the wall behind `from` to the wall
// beyond `to` (walls met by the centre line).
std::pair<double, double> CentreSpan(const World& world, const Corridor& c) {
  const Eigen::Vector2d ax = c.Axis();
  const Eigen::Vector2d mid = 0.5 * (c.from + c.to);
  const auto ahead = world.CastWalls(mid, ax);
  const auto behind = world.CastWalls(mid, -ax);
  const double half = c.Length() / 2;
  return {behind ? half - behind->first : -c.width_m / 2, ahead ? half + ahead->first : c.Length() + c.width_m / 2};
}

}  // namespace

std::string SweepOptions::Validate() const {
  std::ostringstream why;
  if (!(spacing_m > 0)) why << "spacing_m must be positive; ";
  if (!(step_deg > 0) || !(max_deg >= min_deg)) why << "need step_deg > 0 and max_deg >= min_deg; ";
  if (!(rate_hz > 0)) why << "rate_hz must be positive; ";
  if (!(end_margin_m >= 0)) why << "end_margin_m must not be negative; ";
  return Join(why);
}

std::string DriveOptions::Validate() const {
  std::ostringstream why;
  if (lateral_m.empty()) why << "lateral_m needs at least one offset; ";
  if (!(speed_mps > 0) || !(rate_hz > 0)) why << "speed_mps and rate_hz must be positive; ";
  if (!(start_margin_m >= 0) || !(stop_dist_m >= 0)) why << "start_margin_m and stop_dist_m must not be negative; ";
  return Join(why);
}

std::string CreepOptions::Validate() const {
  std::ostringstream why;
  if (!(step_m > 0) || !(period_s > 0)) why << "step_m and period_s must be positive; ";
  if (!(clearance_m >= 0) || !(stop_dist_m >= 0)) why << "clearance_m and stop_dist_m must not be negative; ";
  return Join(why);
}

std::vector<TimedPose> SweepSchedule(const World& world, const SweepOptions& o) {
  if (const std::string why = o.Validate(); !why.empty()) throw Error("sweep options: " + why);
  const Corridor& c = Pick(world, o.corridor, "sweep");
  const auto [s0, s1] = CentreSpan(world, c);
  const Eigen::Vector2d ax = c.Axis();
  const double axis_yaw = std::atan2(ax.y(), ax.x());
  std::vector<TimedPose> out;
  double t = 0;
  const double dt = 1.0 / o.rate_hz;
  const int steps = static_cast<int>(std::floor((o.max_deg - o.min_deg) / o.step_deg + 1e-9));
  for (double s = s0 + o.end_margin_m; s <= s1 - o.end_margin_m + 1e-9; s += o.spacing_m) {
    const Eigen::Vector2d p = c.from + ax * s;
    for (int i = 0; i <= steps; ++i) {
      out.push_back({t, {p.x(), p.y(), WrapPi(axis_yaw + DegToRad(o.min_deg + i * o.step_deg))}});
      t += dt;
    }
    t += o.spacing_m / 0.4;  // the drive to the next station at 0.4 m/s
  }
  if (out.empty()) throw Error(fmt::format("{}: corridor '{}' is too short for a sweep", world.source, c.name));
  return out;
}

std::vector<TimedPose> DriveSchedule(const World& world, const DriveOptions& o) {
  if (const std::string why = o.Validate(); !why.empty()) throw Error("drive options: " + why);
  const Corridor& c = Pick(world, o.corridor, "drive");
  const auto [s0, s1] = CentreSpan(world, c);
  const Eigen::Vector2d ax = c.Axis(), left(-ax.y(), ax.x());
  const double axis_yaw = std::atan2(ax.y(), ax.x());
  const double step = o.speed_mps / o.rate_hz;
  std::vector<TimedPose> out;
  double t = 0;
  for (double lat : o.lateral_m) {
    if (std::abs(lat) > c.width_m / 2 - world.robot.radius_m)
      throw Error(fmt::format("{}: drive lateral offset {:.2f} m does not fit corridor '{}' (width {:.2f} m, robot radius {:.2f} m)",
                              world.source, lat, c.name, c.width_m, world.robot.radius_m));
    const double start = s0 + std::max(o.start_margin_m, world.robot.radius_m);
    const double stop = s1 - std::max(o.stop_dist_m, world.robot.radius_m);
    for (double s = start; s <= stop + 1e-9; s += step) {
      const Eigen::Vector2d p = c.from + ax * s + left * lat;
      out.push_back({t, {p.x(), p.y(), axis_yaw}});
      t += 1.0 / o.rate_hz;
    }
    t += 5.0;  // the walk back to the start of the next pass
  }
  if (out.empty()) throw Error(fmt::format("{}: corridor '{}' is too short for a drive", world.source, c.name));
  return out;
}

std::vector<TimedPose> CreepSchedule(const World& world, const CreepOptions& o) {
  if (const std::string why = o.Validate(); !why.empty()) throw Error("creep options: " + why);
  const Corridor& c = Pick(world, o.corridor, "creep");
  const auto [s0, s1] = CentreSpan(world, c);
  const Eigen::Vector2d ax = c.Axis(), left(-ax.y(), ax.x());
  // A* over a 5 cm grid of the corridor, cost = length + a penalty near obstacles.
  const double cell = 0.05;
  const double r = world.robot.radius_m;
  const double len = s1 - s0;
  const int nu = static_cast<int>(len / cell) + 1, nv = static_cast<int>(c.width_m / cell) + 1;
  auto to_world = [&](int iu, int iv) { return Eigen::Vector2d(c.from + ax * (s0 + iu * cell) + left * (-c.width_m / 2 + iv * cell)); };
  std::vector<double> clearance(static_cast<std::size_t>(nu) * nv);
  for (int iu = 0; iu < nu; ++iu)
    for (int iv = 0; iv < nv; ++iv) {
      const Eigen::Vector2d p = to_world(iu, iv);
      clearance[iu * nv + iv] = world.IsFree(p) ? std::min(world.DistanceToWalls(p), world.DistanceToObstacles(p)) : -1.0;
    }
  auto ok = [&](int iu, int iv) { return iu >= 0 && iv >= 0 && iu < nu && iv < nv && clearance[iu * nv + iv] >= r + 0.02; };
  const int start_u = static_cast<int>(std::max(1.0, r + 0.3) / cell), goal_u = static_cast<int>((len - std::max(o.stop_dist_m, r)) / cell);
  const int mid_v = nv / 2;
  int start_v = -1;
  for (int dv = 0; dv < nv && start_v < 0; ++dv)
    for (int sgn : {1, -1})
      if (start_v < 0 && ok(start_u, mid_v + sgn * dv)) start_v = mid_v + sgn * dv;
  if (start_v < 0 || goal_u <= start_u)
    throw Error(fmt::format("{}: creep: no free start in corridor '{}'", world.source, c.name));
  std::vector<double> cost(clearance.size(), std::numeric_limits<double>::infinity());
  std::vector<int> parent(clearance.size(), -1);
  using Node = std::pair<double, int>;
  std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
  const int start = start_u * nv + start_v;
  cost[start] = 0;
  open.push({0, start});
  int goal = -1;
  while (!open.empty()) {
    const auto [f, idx] = open.top();
    open.pop();
    const int iu = idx / nv, iv = idx % nv;
    if (iu >= goal_u) {
      goal = idx;
      break;
    }
    if (f > cost[idx] + (goal_u - iu) * cell + 1e-9) continue;
    for (int du = -1; du <= 1; ++du)
      for (int dv = -1; dv <= 1; ++dv) {
        if ((du == 0 && dv == 0) || !ok(iu + du, iv + dv)) continue;
        const int j = (iu + du) * nv + iv + dv;
        const double near = std::max(0.0, r + o.clearance_m + 0.3 - clearance[j]);
        const double g = cost[idx] + cell * std::hypot(du, dv) * (1.0 + 4.0 * near) + 0.002 * std::abs(iv + dv - mid_v) * cell;
        if (g < cost[j]) {
          cost[j] = g;
          parent[j] = idx;
          open.push({g + (goal_u - iu - du) * cell, j});
        }
      }
  }
  if (goal < 0) throw Error(fmt::format("{}: creep: the obstacles block corridor '{}'", world.source, c.name));
  std::vector<Eigen::Vector2d> path;
  for (int i = goal; i >= 0; i = parent[i]) path.push_back(to_world(i / nv, i % nv));
  std::reverse(path.begin(), path.end());
  // Smooth (moving average over about 0.5 m) then resample every step_m.
  std::vector<Eigen::Vector2d> smooth(path.size());
  const int half = 5;
  for (std::size_t i = 0; i < path.size(); ++i) {
    Eigen::Vector2d s = Eigen::Vector2d::Zero();
    int n = 0;
    for (int k = -half; k <= half; ++k) {
      const int j = std::clamp(static_cast<int>(i) + k, 0, static_cast<int>(path.size()) - 1);
      s += path[j];
      ++n;
    }
    smooth[i] = s / n;
  }
  std::vector<TimedPose> out;
  double t = 0, carry = 0;
  Eigen::Vector2d prev = smooth.front();
  out.push_back({t, {prev.x(), prev.y(), std::atan2(ax.y(), ax.x())}});
  for (std::size_t i = 1; i < smooth.size(); ++i) {
    const Eigen::Vector2d seg = smooth[i] - prev;
    double seg_len = seg.norm();
    if (seg_len < 1e-9) continue;
    const Eigen::Vector2d dir = seg / seg_len;
    double pos = o.step_m - carry;
    while (pos <= seg_len) {
      const Eigen::Vector2d p = prev + dir * pos;
      t += o.period_s;
      out.push_back({t, {p.x(), p.y(), std::atan2(dir.y(), dir.x())}});
      pos += o.step_m;
    }
    carry = seg_len - (pos - o.step_m);
    prev = smooth[i];
  }
  // Headings: along the path, smoothed over a few steps.
  for (std::size_t i = 0; i + 1 < out.size(); ++i) {
    const std::size_t j = std::min(out.size() - 1, i + 8);
    const Eigen::Vector2d d = out[j].pose.Translation() - out[i].pose.Translation();
    if (d.norm() > 1e-6) out[i].pose.yaw = std::atan2(d.y(), d.x());
  }
  if (out.size() > 1) out.back().pose.yaw = out[out.size() - 2].pose.yaw;
  return out;
}

}  // namespace squint::sim
