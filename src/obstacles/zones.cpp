// The paper's D(u, v) simulation (eq. 11–15) for a camera and motion, and the zone rows it implies.
#include "squint/obstacles/zones.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "squint/core/error.hpp"
#include "squint/core/pose.hpp"
#include "squint/obstacles/ipt_geometry.hpp"

namespace squint::obstacles {

std::string ZoneOptions::Validate() const {
  std::ostringstream why;
  if (!(dst_m > 0.0 && std::isfinite(dst_m))) why << "dst_m must be positive; ";
  if (!(step_m > 0.0 && std::isfinite(step_m))) why << "step_m must be positive; ";
  if (!(zone2_min_d_m > 0.0 && std::isfinite(zone2_min_d_m))) why << "zone2_min_d_m must be positive; ";
  if (!(zone0_max_d_m >= 0.0 && zone0_max_d_m < zone2_min_d_m)) why << "zone0_max_d_m must lie in [0, zone2_min_d_m); ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

namespace {
// §4.2 steps I–III for one pixel: the scene point at DST along the ray (eq. 11–14), its image after
// the forward step, and the discrepancy of the two floor back-projections.
double SimulatedD(const CameraModel& camera, const Pose2& world_T_second, const Eigen::Vector2d& pixel,
                  double dst_m) {
  const Eigen::Vector3d ray = camera.PixelRayRobot(pixel);
  Eigen::Vector3d point = camera.RobotCameraCentre() + dst_m * ray;
  if (point.z() <= 0.0) return 0.0;  // the sphere is under the floor here: a floor point, D = 0
  const Pose2 second_T_world = world_T_second.Inverse();
  const Eigen::Vector2d xy = second_T_world.Apply(point.head<2>());
  const auto pixel2 = camera.Project({xy.x(), xy.y(), point.z()});
  if (!pixel2) return 0.0;
  const auto d = Discrepancy(camera, Pose2{}, pixel, world_T_second, *pixel2);
  return d ? *d : 0.0;
}
}  // namespace

std::vector<double> SimulateDiscrepancyMap(const CameraModel& camera, const ZoneOptions& options) {
  SQUINT_ENSURE(camera.Validate().empty(), camera.Validate());
  SQUINT_ENSURE(options.Validate().empty(), options.Validate());
  std::vector<double> map(static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height), 0.0);
  const Pose2 world_T_second{options.step_m, 0.0, 0.0};
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u)
      map[static_cast<std::size_t>(v) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(u)] =
          SimulatedD(camera, world_T_second, {u, v}, options.dst_m);
  return map;
}

ZoneLayout ComputeZoneLayout(const CameraModel& camera, const ZoneOptions& options) {
  SQUINT_ENSURE(camera.Validate().empty(), camera.Validate());
  SQUINT_ENSURE(options.Validate().empty(), options.Validate());
  // Per-row maximum of D over the columns, on a fine row grid (the zones are rows, §6.2).
  const Pose2 world_T_second{options.step_m, 0.0, 0.0};
  const double cx = camera.cx;
  // The horizon row of the image centre column through the camera model (eq. 10 generalised):
  // the first row, going down, whose ray points below the horizon.
  constexpr double kStep = 0.25;
  ZoneLayout layout;
  double v = 0.0;
  while (v < camera.height && AboveHorizon(camera, {cx, v})) v += kStep;
  layout.horizon_row = v;
  std::vector<std::pair<double, double>> profile;  // (row, max D)
  for (double row = v; row < camera.height; row += kStep) {
    double best = 0.0;
    for (int u = 0; u < camera.width; u += std::max(1, camera.width / 32))
      best = std::max(best, SimulatedD(camera, world_T_second, {u, row}, options.dst_m));
    profile.emplace_back(row, best);
  }
  layout.zone2_end_row = layout.zone1_end_row = camera.height;
  bool found2 = false;
  for (std::size_t i = 0; i < profile.size(); ++i) {
    if (!found2 && profile[i].second < options.zone2_min_d_m) {
      layout.zone2_end_row = profile[i].first;
      found2 = true;
    }
    if (found2 && profile[i].second <= options.zone0_max_d_m) {
      layout.zone1_end_row = profile[i].first;
      break;
    }
  }
  return layout;
}

}  // namespace squint::obstacles
