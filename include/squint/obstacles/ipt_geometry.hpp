// Inverse perspective transformation (paper §3.1–3.2, §4.1): back-projection of a pixel onto the
// floor z = 0 with the frame's odometry pose, the discrepancy D (eq. 4), and the horizon (eq. 10).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "squint/core/camera.hpp"
#include "squint/core/pose.hpp"

namespace squint::obstacles {

// Eq. 2–3 in general form: the pixel's ray through the camera model and mount meets the floor at a
// robot-frame point, which world_T_robot maps into the world. None above the horizon (λ < 0, §4.1).
std::optional<Eigen::Vector2d> FloorPointWorld(const CameraModel& camera, const Pose2& world_T_robot,
                                               const Eigen::Vector2d& pixel);

// Eq. 4: distance between the two floor points of a feature seen at `previous_pixel` from
// world_T_previous and at `current_pixel` from world_T_current. None when either pixel lies at or
// above the horizon.
std::optional<double> Discrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                  const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                  const Eigen::Vector2d& current_pixel);

// Eq. 4 with a sign: the floor point of a feature moves by dF = (1 - s)·dC when the camera centre
// moves by dC, with s = h / (h - z) for a scene point at height z. Points above the floor (z > 0)
// move against the camera (s > 1), floor points stay, and mirror images seen in a specular floor
// (virtual points below it, z < 0) move with it. Returns -dF·dC/|dC| (metres): positive for
// points above the floor, about zero on it, negative for mirror images; |value| <= D. None when
// either pixel lies at or above the horizon or the camera did not move.
std::optional<double> SignedDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                        const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                        const Eigen::Vector2d& current_pixel);

// The discrepancy with the floor hypothesis widened to mirror images: every static point's floor
// point moves by dF = k·dC along the camera centre's motion dC, with k = 0 on the floor,
// 0 < k < 1 for a mirror image below a specular floor (k = d / (h + d) at depth d) and k < 0 above
// the floor (k = -z / (h - z)). Returns the distance from dF to the segment {k·dC : 0 <= k <= 1}
// (metres): equal to D (eq. 4) for points above the floor, only the part of dF off the motion line
// (noise) for floor points and their reflections. None where Discrepancy() has none or the camera
// did not move.
std::optional<double> MirrorAwareDiscrepancy(const CameraModel& camera, const Pose2& world_T_previous,
                                             const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                             const Eigen::Vector2d& current_pixel);

// Discrepancy(), SignedDiscrepancy() and MirrorAwareDiscrepancy() of one correspondence from one
// back-projection of each pixel (what the pipeline needs per feature). None where Discrepancy() has
// none or the camera did not move.
struct Discrepancies {
  double plain_m = 0.0;
  double signed_m = 0.0;
  double mirror_aware_m = 0.0;
};
std::optional<Discrepancies> AllDiscrepancies(const CameraModel& camera, const Pose2& world_T_previous,
                                              const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                              const Eigen::Vector2d& current_pixel);

// Epipolar residual of a correspondence under the motion known from odometry (paper §3.3's epipolar
// constraint, with F fixed by the poses and the camera mount instead of estimated): every static
// scene point — on the floor, above it, or a mirror image below it — has its two viewing rays in one
// plane with the baseline. Returns the larger of the two ray-to-epipolar-plane angles, in pixels
// (angle × fx). A mismatch, or a point that moved, leaves the plane. 0 for rays along the baseline
// (the epipole, where the plane is undefined). None when the camera centre did not move.
std::optional<double> MotionEpipolarErrorPx(const CameraModel& camera, const Pose2& world_T_previous,
                                            const Eigen::Vector2d& previous_pixel, const Pose2& world_T_current,
                                            const Eigen::Vector2d& current_pixel);

// Eq. 10 generalised: true when the pixel's ray does not point below the horizon (λ would be
// negative), so the feature is an obstacle without D. The ray is undistorted by the camera model.
bool AboveHorizon(const CameraModel& camera, const Eigen::Vector2d& pixel);

// What the pipeline measures per feature of one frame pair, from one viewing ray per pixel and the
// poses' rotations computed once per pair: the same values as AboveHorizon(current pixel),
// AllDiscrepancies() and MotionEpipolarErrorPx() (they share this code).
struct FeatureMeasures {
  bool above_horizon = false;                  // of the later pixel
  std::optional<Discrepancies> discrepancies;  // only computed below the horizon
  std::optional<double> motion_epipolar_px;
};
class PairGeometry {
 public:
  PairGeometry(const CameraModel& camera, const Pose2& world_T_previous, const Pose2& world_T_current);
  FeatureMeasures Measure(const Eigen::Vector2d& previous_pixel, const Eigen::Vector2d& current_pixel) const;

 private:
  struct Frame {  // a pose with its yaw's cosine and sine
    double x, y, c, s;
    // Pose2::Apply's arithmetic.
    Eigen::Vector2d Apply(const Eigen::Vector2d& p) const {
      return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
    }
  };
  const CameraModel& camera_;
  Frame previous_, current_;
  Eigen::Vector2d centre_previous_, centre_current_;  // the camera centre's floor point in the world
};

}  // namespace squint::obstacles
