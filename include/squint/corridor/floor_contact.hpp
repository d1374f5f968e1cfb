// Distance to the end of the corridor from where the end wall stands on the floor, in the full
// camera frame (FloorContactOptions in options.hpp says how and why).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/corridor/glance.hpp"
#include "squint/corridor/options.hpp"

namespace squint::corridor {

// Where the lined-wall rule searched a column again, the frame's reading stands only when its
// columns' edges lie on one line: at least min_column_fraction of the columns within this many
// rows of their median. An end wall's foot across the centre columns (±2°) is one row to within
// a fraction of a row even at a 10° heading (its depth changes by tan 10° · 4° ≈ 1 %); an edge
// found again on a brick wall is a course or a joint that differs from column to column
// (docs/calibration.md, session 15b).
inline constexpr double kLinedWallRowSpread = 1.0;

class FloorContact {
 public:
  // `camera`: the camera of the frames given to Measure (intrinsics, height and pitch). Throws
  // squint::Error when it has no intrinsics, no height, or the horizon is not inside the frame.
  FloorContact(const CameraModel& camera, const FloorContactOptions& options);
  // Why `camera` cannot serve (empty when it can): the constructor's camera checks.
  static std::string CameraProblem(const CameraModel& camera);

  // The frame's reading in metres along the robot's axis, or none (frame of another size, too
  // few columns with an edge below the horizon, or a reading outside [min_m, max_m]). Allocates
  // nothing.
  std::optional<double> Measure(const PixelView& frame);

 private:
  // The boundary row (pixel-centre coordinates, sub-pixel) of column u's profile, scanning down
  // from the horizon; none without a step of min_step.
  std::optional<double> BoundaryRow(const PixelView& frame, int u);
  // The first edge of at least `min_step` in profile_ (filled from top_row_ down), refined and
  // sub-pixel as BoundaryRow describes; none without one.
  std::optional<double> EdgeRow(double min_step) const;
  // Whether column u shows a step of min_step between neighbouring rows within the band of rows
  // just above the horizon as deep as `edge_row` lies below it (the lined-wall rule).
  bool LinedAbove(const PixelView& frame, int u, double edge_row) const;
  // The mean grey of columns u − 1 … u + 1 in row v.
  double ColumnGrey(const PixelView& frame, int u, int v) const;
  // |profile_(v + 1) − profile_(v)|.
  double Step(int v) const;

  CameraModel camera_;
  FloorContactOptions options_;
  int top_row_ = 0;       // first row below the horizon
  int u_first_ = 0;       // the columns read
  int u_last_ = 0;
  std::vector<double> profile_;
  std::vector<double> readings_;
  std::vector<double> rows_;  // the answering columns' edge rows
  bool lined_ = false;        // the lined-wall rule searched again in some column of this frame
};

// The floor contact's motion test (FloorContactOptions::motion_window_m): whether the recent raw
// readings move under the odometry as one point on the floor does. A floor point at distance E
// from where the travel was counted is read E − t at travel t; a feature at height z on a wall
// at D reads (D − t) · h / (h − z), which shrinks faster, and a detector that jumps between
// brick courses scatters. The test is in image rows, the detector's own resolution: far away
// a row spans metres, near the end centimetres.
class FloorMotionCheck {
 public:
  // `camera`: as FloorContact's (intrinsics, height, pitch; throws squint::Error otherwise).
  FloorMotionCheck(const CameraModel& camera, const FloorContactOptions& options);
  // Forgets every reading (a restart of the distance history: standing, turning in place).
  void Reset();
  // Adds this frame: `travel_m`, the odometry travel accumulated since the last Reset (not
  // decreasing); `reading`, its raw floor-contact reading in metres, or none. Returns true when
  // this frame has a reading and the readings within the last motion_window_m of travel pass:
  // at least motion_min_readings of them, the oldest at least half the window back, and at
  // least motion_min_fraction of them inliers, i.e. within motion_tol_rows of the row of the
  // floor point at E − t, E the median of travel + reading. Allocates nothing.
  bool Update(double travel_m, std::optional<double> reading);
  // The row (pixel-centre coordinates, sub-pixel) where the floor `dist_m` ahead of the camera
  // appears; rows grow downward from the horizon.
  double FloorRow(double dist_m) const;

 private:
  CameraModel camera_;
  FloorContactOptions options_;
  std::array<double, kMaxFloorMotionReadings> travel_{};
  std::array<double, kMaxFloorMotionReadings> reading_{};
  std::array<double, kMaxFloorMotionReadings> row_{};  // FloorRow(reading_), computed once
  std::array<double, kMaxFloorMotionReadings> scratch_{};
  int head_ = 0;   // the newest reading
  int count_ = 0;
};

}  // namespace squint::corridor
