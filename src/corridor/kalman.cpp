// The heading / distance-to-end Kalman filter with odometry as the process model (kalman.hpp).
#include "squint/corridor/kalman.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::corridor {

std::string CorridorKalmanOptions::Validate() const {
  if (!(heading_process_std_deg >= 0.0) || !(dist_process_std_m >= 0.0) ||
      !(heading_process_std_deg_per_sqrt_s >= 0.0) || !std::isfinite(heading_process_std_deg_per_sqrt_s))
    return "process std must be >= 0";
  if (!(heading_odom_noise_fraction >= 0.0) || !(dist_odom_noise_fraction >= 0.0))
    return "odometry noise fractions must be >= 0";
  if (!(no_odom_heading_std_deg >= 0.0) || !(no_odom_dist_std_m >= 0.0)) return "no-odometry std must be >= 0";
  if (!(gate_chi2 > 0.0)) return "gate_chi2 must be positive";
  if (reinit_after_rejections < 1) return "reinit_after_rejections must be >= 1";
  if (!(min_dist_m >= 0.0)) return "min_dist_m must be >= 0";
  return {};
}

CorridorKalman::CorridorKalman(const CorridorKalmanOptions& options) : options_(options) {
  const std::string bad = options_.Validate();
  if (!bad.empty()) throw Error("kalman options: " + bad);
}

void CorridorKalman::Reset() {
  x_.setZero();
  p_.setZero();
  has_heading_ = has_dist_ = false;
  heading_rejections_ = dist_rejections_ = 0;
}

void CorridorKalman::SetHeading(double heading_deg, double std_deg) {
  if (!std::isfinite(heading_deg) || !(std_deg > 0.0) || !std::isfinite(std_deg)) return;
  x_(0) = heading_deg;
  p_(0, 0) = std_deg * std_deg;
  p_(0, 1) = p_(1, 0) = 0.0;
  has_heading_ = true;
  heading_rejections_ = 0;
}

void CorridorKalman::Predict(const std::optional<Pose2>& prev_T_curr, double dt_s) {
  Eigen::Matrix2d f = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  if (prev_T_curr) {
    const double h = DegToRad(x_(0));
    const double dx = prev_T_curr->x, dy = prev_T_curr->y;
    const double dyaw_deg = RadToDeg(WrapPi(prev_T_curr->yaw));
    const double along = dx * std::cos(h) - dy * std::sin(h);
    // ∂(dist')/∂h (per degree) for the linearisation.
    f(1, 0) = (dx * std::sin(h) + dy * std::cos(h)) * DegToRad(1.0);
    x_(0) = RadToDeg(WrapPi(DegToRad(x_(0) + dyaw_deg)));
    x_(1) = std::max(options_.min_dist_m, x_(1) - along);
    const double step_std = (options_.heading_process_std_deg_per_sqrt_s > 0.0 && dt_s > 0.0 && std::isfinite(dt_s))
                                ? options_.heading_process_std_deg_per_sqrt_s * std::sqrt(dt_s)
                                : options_.heading_process_std_deg;
    const double sh = step_std + options_.heading_odom_noise_fraction * std::abs(dyaw_deg);
    const double sd = options_.dist_process_std_m + options_.dist_odom_noise_fraction * std::hypot(dx, dy);
    q(0, 0) = sh * sh;
    q(1, 1) = sd * sd;
  } else {
    q(0, 0) = options_.no_odom_heading_std_deg * options_.no_odom_heading_std_deg;
    q(1, 1) = options_.no_odom_dist_std_m * options_.no_odom_dist_std_m;
  }
  if (!has_dist_) f(1, 0) = 0.0;  // an unknown distance carries no correlation
  p_ = f * p_ * f.transpose() + q;
}

bool CorridorKalman::Update(int i, double z, double std, bool& has, int& rejections) {
  if (!std::isfinite(z) || !(std > 0.0) || !std::isfinite(std)) return false;
  const double r = std * std;
  if (!has || rejections >= options_.reinit_after_rejections) {
    // (Re)initialise this state from the measurement; drop its correlation with the other.
    x_(i) = z;
    p_(i, i) = r;
    p_(0, 1) = p_(1, 0) = 0.0;
    has = true;
    rejections = 0;
    return true;
  }
  const double innovation = (i == 0) ? AngleDiff(DegToRad(z), DegToRad(x_(0))) * 180.0 / kPi : z - x_(1);
  const double s = p_(i, i) + r;
  if (innovation * innovation / s > options_.gate_chi2) {
    ++rejections;
    return false;
  }
  rejections = 0;
  const Eigen::Vector2d k = p_.col(i) / s;
  x_ += k * innovation;
  // Joseph form keeps the covariance symmetric positive semi-definite.
  Eigen::RowVector2d h = Eigen::RowVector2d::Zero();
  h(i) = 1.0;
  const Eigen::Matrix2d ikh = Eigen::Matrix2d::Identity() - k * h;
  p_ = ikh * p_ * ikh.transpose() + k * r * k.transpose();
  x_(1) = std::max(options_.min_dist_m, x_(1));
  return true;
}

bool CorridorKalman::UpdateHeading(double heading_deg, double std_deg) {
  return Update(0, heading_deg, std_deg, has_heading_, heading_rejections_);
}

bool CorridorKalman::UpdateDistance(double dist_m, double std_m) {
  return Update(1, dist_m, std_m, has_dist_, dist_rejections_);
}

std::optional<double> CorridorKalman::HeadingDeg() const {
  if (!has_heading_) return std::nullopt;
  return x_(0);
}

std::optional<double> CorridorKalman::DistanceM() const {
  if (!has_dist_) return std::nullopt;
  return x_(1);
}

double CorridorKalman::HeadingStdDeg() const { return std::sqrt(std::max(0.0, p_(0, 0))); }
double CorridorKalman::DistanceStdM() const { return std::sqrt(std::max(0.0, p_(1, 1))); }

}  // namespace squint::corridor
