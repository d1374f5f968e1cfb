// A Kalman filter over the robot's heading in the corridor and its distance to the corridor's
// end, with odometry as the process model: the paper's suggested alternative (§5.3) to the
// per-frame weighted average of the measures. Allocation-free; one instance per run.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "squint/core/pose.hpp"

namespace squint::corridor {

struct CorridorKalmanOptions {
  // Process noise added per prediction step, plus a part proportional to the odometry motion
  // (odometry drifts with what it measures).
  double heading_process_std_deg = 0.3;
  // When > 0 and Predict() is given the frame interval dt, the heading's per-step noise is this
  // times sqrt(dt) instead of heading_process_std_deg (a random walk per second, the same at 4 Hz
  // and at 30 Hz). 0 (default): per step.
  double heading_process_std_deg_per_sqrt_s = 0.0;
  double heading_odom_noise_fraction = 0.05;  // of |Δyaw|
  double dist_process_std_m = 0.02;
  double dist_odom_noise_fraction = 0.05;     // of the travelled distance
  // Process noise per step when no odometry is given (state held, uncertainty grown).
  double no_odom_heading_std_deg = 3.0;
  double no_odom_dist_std_m = 0.3;
  // Measurements whose squared Mahalanobis distance to the prediction exceeds this are
  // rejected (9 = 3σ for one dimension).
  double gate_chi2 = 9.0;
  // After this many consecutive rejections of one state, it is re-initialised from the next
  // measurement (the corridor changed: a turn, a new end wall).
  int reinit_after_rejections = 20;
  // Lower bound on the distance state (the camera cannot be behind the end wall).
  double min_dist_m = 0.0;

  std::string Validate() const;  // empty when valid
};

class CorridorKalman {
 public:
  explicit CorridorKalman(const CorridorKalmanOptions& options = {});

  void Reset();
  // Sets the heading state to heading_deg with standard deviation std_deg (a prior from outside,
  // e.g. the caller's own axis); the distance state is kept, their correlation dropped.
  void SetHeading(double heading_deg, double std_deg);
  // Propagates the state by the odometry motion between the previous and this frame, expressed
  // in the previous robot frame (prev_T_curr = Between(world_T_prev, world_T_curr)); none when
  // odometry is unknown. Heading rotates by Δyaw; the distance shrinks by the motion's
  // component along the corridor axis, Δx·cos(h) − Δy·sin(h).
  // dt_s: the time since the previous frame (0 = unknown; see heading_process_std_deg_per_sqrt_s).
  void Predict(const std::optional<Pose2>& prev_T_curr, double dt_s = 0.0);
  // Fuses one heading measurement with its standard deviation; returns false when gated out.
  bool UpdateHeading(double heading_deg, double std_deg);
  // Fuses one distance-to-end measurement; returns false when gated out.
  bool UpdateDistance(double dist_m, double std_m);

  bool HasHeading() const { return has_heading_; }
  bool HasDistance() const { return has_dist_; }
  std::optional<double> HeadingDeg() const;
  std::optional<double> DistanceM() const;
  double HeadingStdDeg() const;
  double DistanceStdM() const;
  // State [heading_deg, dist_m] and its covariance.
  const Eigen::Vector2d& State() const { return x_; }
  const Eigen::Matrix2d& Covariance() const { return p_; }

 private:
  bool Update(int index, double z, double std, bool& has, int& rejections);

  CorridorKalmanOptions options_;
  Eigen::Vector2d x_ = Eigen::Vector2d::Zero();
  Eigen::Matrix2d p_ = Eigen::Matrix2d::Zero();
  bool has_heading_ = false;
  bool has_dist_ = false;
  int heading_rejections_ = 0;
  int dist_rejections_ = 0;
};

}  // namespace squint::corridor
