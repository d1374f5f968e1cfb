// The local polar occupancy map (obstacle paper §5.3).
#include "squint/obstacles/polar_map.hpp"

#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string PolarMapOptions::Validate() const {
  if (!(roi_radius_m > 0.0 && roi_radius_m <= 100.0)) return "polar.roi_radius_m must be in (0, 100]";
  if (!(sector_deg >= 0.5 && sector_deg <= 90.0)) return "polar.sector_deg must be in [0.5, 90]";
  const double n = 180.0 / sector_deg;
  if (std::abs(n - std::round(n)) > 1e-6) return "polar.sector_deg must divide 180 into whole sectors";
  if (min_contacts < 1) return "polar.min_contacts must be >= 1";
  if (min_ground_features < 1) return "polar.min_ground_features must be >= 1";
  if (!(min_ground_range_m >= 0.0 && min_ground_range_m <= roi_radius_m))
    return "polar.min_ground_range_m must be in [0, roi_radius_m]";
  return {};
}

bool FloorBearingInView(const CameraModel& camera, double range_m, double bearing_deg) {
  const double b = DegToRad(bearing_deg);
  const std::optional<Eigen::Vector2d> px =
      camera.Project(Eigen::Vector3d(range_m * std::cos(b), range_m * std::sin(b), 0.0));
  if (!px) return false;
  return px->x() >= -0.5 && px->x() <= camera.width - 0.5 && px->y() >= -0.5 && px->y() <= camera.height - 0.5;
}

PolarMapper::PolarMapper(const CameraModel& camera, PolarMapOptions options) : options_(options) {
  const std::string problem = options_.Validate();
  SQUINT_ENSURE(problem.empty(), problem);
  const int n = static_cast<int>(std::lround(180.0 / options_.sector_deg));
  map_.roi_radius_m = options_.roi_radius_m;
  map_.sector_deg = options_.sector_deg;
  map_.sectors.resize(n);
  for (int i = 0; i < n; ++i) {
    PolarSector& s = map_.sectors[i];
    s.start_deg = -90.0 + i * options_.sector_deg;
    s.end_deg = s.start_deg + options_.sector_deg;
    s.centre_deg = 0.5 * (s.start_deg + s.end_deg);
    s.in_view = FloorBearingInView(camera, options_.roi_radius_m, s.start_deg) &&
                FloorBearingInView(camera, options_.roi_radius_m, s.end_deg);
  }
}

std::optional<int> PolarMapper::SectorOf(double bearing_deg) const {
  if (!(bearing_deg >= -90.0 && bearing_deg <= 90.0)) return std::nullopt;
  const int n = static_cast<int>(map_.sectors.size());
  const int i = static_cast<int>(std::floor((bearing_deg + 90.0) / options_.sector_deg));
  return std::clamp(i, 0, n - 1);
}

const PolarMap& PolarMapper::Build(std::span<const ContactPoint> contacts,
                                   std::span<const Eigen::Vector2d> ground_floor_m) {
  for (PolarSector& s : map_.sectors) {
    s.contacts = 0;
    s.ground = 0;
    s.range_m.reset();
    s.nearest_m.reset();
  }
  for (const ContactPoint& c : contacts) {
    const std::optional<int> i = SectorOf(c.bearing_deg);
    if (!i) continue;  // behind the robot: outside the semicircle
    PolarSector& s = map_.sectors[*i];
    if (!s.nearest_m || c.range_m < *s.nearest_m) s.nearest_m = c.range_m;
    if (c.range_m > options_.roi_radius_m) continue;
    ++s.contacts;
    if (!s.range_m || c.range_m < *s.range_m) s.range_m = c.range_m;
  }
  for (const Eigen::Vector2d& g : ground_floor_m) {
    if (g.norm() > options_.roi_radius_m || g.norm() < options_.min_ground_range_m) continue;
    if (const std::optional<int> i = SectorOf(RadToDeg(std::atan2(g.y(), g.x())))) ++map_.sectors[*i].ground;
  }
  for (PolarSector& s : map_.sectors) {
    const bool floor_seen = !options_.free_needs_ground || s.ground >= options_.min_ground_features;
    if (s.contacts >= options_.min_contacts) s.state = SectorState::kOccupied;
    else s.state = s.in_view && floor_seen ? SectorState::kFree : SectorState::kUnseen;
    if (s.state != SectorState::kOccupied) s.range_m.reset();
  }
  return map_;
}

}  // namespace squint::obstacles
