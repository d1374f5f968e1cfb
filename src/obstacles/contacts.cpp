// Contact points: floor back-projection, range and bearing (obstacle paper eq. 16).
#include "squint/obstacles/contacts.hpp"

#include <cmath>

#include "squint/core/angles.hpp"

namespace squint::obstacles {

std::optional<ContactPoint> ContactFromPixel(const CameraModel& camera, const Eigen::Vector2d& pixel) {
  const std::optional<Eigen::Vector2d> floor = camera.FloorPoint(pixel);
  if (!floor || !floor->allFinite()) return std::nullopt;
  ContactPoint c;
  c.pixel = pixel;
  c.floor_m = *floor;
  // eq. 16 with the camera at the origin and the direction of motion along +x: dcp = |p|, and
  // the angle to +x, signed counter-clockwise instead of the paper's unsigned arccos.
  c.range_m = floor->norm();
  c.bearing_deg = RadToDeg(std::atan2(floor->y(), floor->x()));
  return c;
}

}  // namespace squint::obstacles
