// The camera model: pinhole intrinsics, plumb-bob distortion, and the mount on the robot
// (height of the optical centre above the floor, pitch about the camera x axis).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace squint {

// Frames: robot x forward, y left, z up, origin on the floor under the rotation centre.
// Camera (OpenCV): x right, y down, z along the optical axis; it sits at (0, 0, height_m) in
// the robot frame looking forward, rotated by pitch_deg about its x axis (negative looks down).
// Pixel centres are at integer coordinates (the centre of a 160-wide image is u = 79.5).
struct CameraModel {
  int width = 0;
  int height = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  double height_m = 0.0;   // optical centre above the floor
  double pitch_deg = 0.0;  // negative looks down
  std::vector<double> distortion;  // OpenCV plumb-bob [k1, k2, p1, p2, k3]; empty = none

  // Empty when valid, otherwise what is wrong (for the caller to wrap with the file name).
  std::string Validate() const;
  bool HasIntrinsics() const { return fx > 0.0 && fy > 0.0; }
  bool HasDistortion() const;

  // The same camera seen at another resolution (for example the 32×24 glance), with the
  // pixel-centre convention preserved: c' = (c + 0.5) * s - 0.5. Distortion is kept (it acts
  // on normalised coordinates).
  CameraModel Scaled(int new_width, int new_height) const;

  // Bearing of image column u in radians, counter-clockwise (left) positive: atan((cx - u) / fx).
  double BearingOfColumn(double u) const;
  // The robot's heading relative to a direction seen at column u (radians): atan((u - cx) / fx),
  // positive when the robot is turned left (the seen direction lies right of the centre).
  double HeadingFromColumn(double u) const { return -BearingOfColumn(u); }

  // Pixel → ideal normalised image coordinates (x/z, y/z), removing distortion iteratively.
  Eigen::Vector2d Normalize(const Eigen::Vector2d& pixel) const;
  // Ideal normalised coordinates → distorted pixel.
  Eigen::Vector2d Denormalize(const Eigen::Vector2d& normalized) const;

  // Rotation taking camera-frame vectors into the robot frame.
  Eigen::Matrix3d RobotRotationCamera() const;
  // The camera's optical centre in the robot frame.
  Eigen::Vector3d RobotCameraCentre() const { return {0.0, 0.0, height_m}; }

  // Unit direction of the ray through a (distorted) pixel, in the robot frame.
  Eigen::Vector3d PixelRayRobot(const Eigen::Vector2d& pixel) const;
  // Where the pixel's ray meets the floor z = 0, in the robot frame; none when the ray does
  // not point below the horizon.
  std::optional<Eigen::Vector2d> FloorPoint(const Eigen::Vector2d& pixel) const;
  // The same for a robot-frame ray from the optical centre (e.g. PixelRayRobot's, computed once).
  std::optional<Eigen::Vector2d> FloorPointOfRay(const Eigen::Vector3d& ray_robot) const;
  // Projects a robot-frame 3-D point into the image (with distortion); none when it is behind
  // the camera. The result may lie outside the image.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& robot_point) const;
  // Image row of the horizon (the rays parallel to the floor) for an undistorted camera:
  // v = cy + fy * tan(pitch).
  double HorizonRow() const;
};

}  // namespace squint
