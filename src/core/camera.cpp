// The camera model's geometry: distortion, rays, floor intersection and projection.
#include "squint/core/camera.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "squint/core/angles.hpp"

namespace squint {

std::string CameraModel::Validate() const {
  std::ostringstream why;
  if (width <= 0 || height <= 0) why << "width and height must be positive; ";
  if (!(fx > 0.0) || !(fy > 0.0) || !std::isfinite(fx) || !std::isfinite(fy)) why << "fx and fy must be positive; ";
  if (!std::isfinite(cx) || !std::isfinite(cy)) why << "cx and cy must be finite; ";
  if (!std::isfinite(height_m) || height_m < 0.0) why << "height_m must be finite and not negative; ";
  if (!std::isfinite(pitch_deg) || std::abs(pitch_deg) >= 89.0) why << "pitch_deg must lie in (-89, 89); ";
  if (!distortion.empty() && distortion.size() != 4 && distortion.size() != 5)
    why << "distortion must have 4 or 5 coefficients [k1, k2, p1, p2, k3]; ";
  for (double d : distortion)
    if (!std::isfinite(d)) why << "distortion coefficients must be finite; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

bool CameraModel::HasDistortion() const {
  for (double d : distortion)
    if (d != 0.0) return true;
  return false;
}

CameraModel CameraModel::Scaled(int new_width, int new_height) const {
  CameraModel c = *this;
  const double sx = static_cast<double>(new_width) / width;
  const double sy = static_cast<double>(new_height) / height;
  c.width = new_width;
  c.height = new_height;
  c.fx = fx * sx;
  c.fy = fy * sy;
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  return c;
}

double CameraModel::BearingOfColumn(double u) const { return std::atan((cx - u) / fx); }

namespace {
struct Coeffs {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};
Coeffs Unpack(const std::vector<double>& d) {
  Coeffs c;
  if (d.size() >= 4) {
    c.k1 = d[0];
    c.k2 = d[1];
    c.p1 = d[2];
    c.p2 = d[3];
  }
  if (d.size() >= 5) c.k3 = d[4];
  return c;
}
Eigen::Vector2d Distort(const Coeffs& k, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3));
  return {x * radial + 2.0 * k.p1 * x * y + k.p2 * (r2 + 2.0 * x * x),
          y * radial + k.p1 * (r2 + 2.0 * y * y) + 2.0 * k.p2 * x * y};
}
}  // namespace

Eigen::Vector2d CameraModel::Normalize(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d distorted((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  if (!HasDistortion()) return distorted;
  const Coeffs k = Unpack(distortion);
  // Fixed-point iteration x <- x + (target - distort(x)), as OpenCV's undistortPoints does.
  Eigen::Vector2d x = distorted;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d err = distorted - Distort(k, x);
    x += err;
    if (err.squaredNorm() < 1e-24) break;
  }
  return x;
}

Eigen::Vector2d CameraModel::Denormalize(const Eigen::Vector2d& normalized) const {
  const Eigen::Vector2d d = HasDistortion() ? Distort(Unpack(distortion), normalized) : normalized;
  return {cx + fx * d.x(), cy + fy * d.y()};
}

Eigen::Matrix3d CameraModel::RobotRotationCamera() const {
  const double p = DegToRad(pitch_deg);
  const double c = std::cos(p), s = std::sin(p);
  Eigen::Matrix3d r;
  // Columns: the camera's x (right), y (down) and z (optical axis) in robot coordinates.
  r.col(0) << 0.0, -1.0, 0.0;
  r.col(1) << s, 0.0, -c;
  r.col(2) << c, 0.0, s;
  return r;
}

Eigen::Vector3d CameraModel::PixelRayRobot(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d n = Normalize(pixel);
  return (RobotRotationCamera() * Eigen::Vector3d(n.x(), n.y(), 1.0)).normalized();
}

std::optional<Eigen::Vector2d> CameraModel::FloorPoint(const Eigen::Vector2d& pixel) const {
  return FloorPointOfRay(PixelRayRobot(pixel));
}

std::optional<Eigen::Vector2d> CameraModel::FloorPointOfRay(const Eigen::Vector3d& d) const {
  if (d.z() >= -1e-9) return std::nullopt;
  const double t = height_m / -d.z();
  return Eigen::Vector2d(t * d.x(), t * d.y());
}

std::optional<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& robot_point) const {
  const Eigen::Vector3d pc = RobotRotationCamera().transpose() * (robot_point - RobotCameraCentre());
  if (pc.z() <= 1e-9) return std::nullopt;
  return Denormalize({pc.x() / pc.z(), pc.y() / pc.z()});
}

double CameraModel::HorizonRow() const { return cy + fy * std::tan(DegToRad(pitch_deg)); }

}  // namespace squint
