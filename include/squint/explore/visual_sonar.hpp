// A "visual sonar" from one small grey frame: in each image column, the lowest row where the
// floor ends (a grey-level step scanning up from the bottom) is where something stands on the
// floor; the camera model (height, pitch, intrinsics) turns that row into a range per bearing
// (the floor-contact idea of the obstacle paper, eq. 16, applied to every column of a 64×48 frame).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/core/image_view.hpp"

namespace squint::explore {

struct VisualSonarOptions {
  int step_window_rows = 2;      // rows averaged on each side of a candidate boundary
  double step_threshold = 14.0;  // grey levels between the mean below and the mean above
  double floor_memory = 0.7;      // running floor mean/variance: weight kept per row upward
  double floor_sigma_factor = 3.0;  // the step must also exceed this many floor spreads
  int min_floor_rows = 2;         // a step with fewer floor rows below it reads as blocked near
  int column_half_width = 1;     // columns averaged on each side (texture suppression)
  int median_half_width = 3;     // ranges are the median over 2m + 1 neighbouring columns
  // A column is blocked near when the order statistic this many ranks nearer than the median is
  // blocked near (0 turns it off): at a wall corner beside far floor the blocked side reaches this
  // many columns farther, so no column there reads the floor beyond the corner (the memory would
  // clear the corner along that ray). Boundaries and far keep the plain median (texture).
  int median_near_bias = 1;
  // A boundary nearer than this (m) wins the same rank early (0 turns it off): a chair leg 4 cm
  // thick 0.7-1.2 m away spans 2-4 columns, which the plain median votes out; within this range
  // the robot must see it. Floor texture that close and 3 columns wide reads as standing too.
  double median_near_range_m = 1.2;
  double max_range_m = 6.0;      // boundaries farther than this (or at the horizon) read as far
  // Columns without a step are told apart (blocked near / unknown) by the floor of the columns
  // with a step; fewer such columns than this: no reference (blocked near).
  int min_reference_columns = 8;
  // Without that reference, a column whose mean grey just below the horizon differs from its
  // bottom rows' by more than this (grey levels) is unknown rather than blocked near: a smooth
  // floor gradient (perspective shading of a floor whose far boundary has no contrast, corridor-2's
  // carpet) and not one surface filling the view (a wall within the blind range looks nearly the
  // same from its foot to camera height). 0 turns it off.
  double gradient_unknown_levels = 30.0;
  // A column whose step lies at the horizon (far: floor all the way) must show the floor at its
  // bottom: where its bottom rows differ from this frame's floor reference by more than this
  // (grey levels) the column is blocked near. Something standing within the blind range and
  // taller than the camera fills the column from the bottom row to its top edge above the
  // horizon, so the only step is that top edge, at the horizon (the obstacle course's dark bin
  // 0.5 m ahead read as floor running 6 m on). 0 turns it off; 40 by default since session 26.
  double far_floor_max_diff = 40.0;
  // > 0: the same test for a step in range at this floor range or farther (metres). Something
  // standing of height H a little under the camera's height hc, at range d, puts its top edge at
  // hc / (hc - H) × d: the default building's bin, 0.45 m tall under a 0.6 m camera, its near side
  // 0.73 m ahead, has its top edge at 2.9 m, and its dark face from the bottom row up read as floor
  // running to a wall there (default, start 7 of seed 70). 0: far steps only; 2 by default since
  // session 36 (docs/explore.md: measured on every seed 1-92).
  double far_floor_from_m = 2.0;
  // The frame's floor reference (the median bottom of the columns with a clear step) taken from
  // the columns whose step is a boundary in range only, when at least min_reference_columns (and
  // 3) have one; far columns join it only otherwise. A box 0.45 m tall filling 50 of 64 columns
  // from 0.17 m away reads far in all of them, its dark bottom became the floor reference, and
  // far_floor_max_diff saw nothing unlike it (the obstacle course, start 7 of seed 52). Off by
  // default (session 27: measured on the obstacle course only; docs/explore.md).
  bool floor_ref_boundaries = false;
  // Floor-material edges (tiles to carpet) are not walls. Above a wall's base a vertical face
  // rises through the horizon; above a floor edge lies more floor, up to the next boundary. A
  // step followed, at least floor_edge_min_rows higher, by a second step below the horizon whose
  // floor range is within [min_ratio, max_ratio] × the first's is read as a floor edge (the column
  // then reports the second step). Anything standing of height H puts its top edge at
  // hc / (hc - H) × its base range (hc: camera height), so objects taller than
  // hc × (1 - 1 / max_ratio) (0.36 m at hc = 0.6 m with 2.5) and horizontal lines on a wall below
  // hc × (1 - 1 / min_ratio) (0.12 m with 1.25) are never taken for floor edges. 0 turns it off.
  double floor_edge_min_ratio = 1.25;
  double floor_edge_max_ratio = 2.5;
  int floor_edge_min_rows = 2;
  // Only steps at least this far (metres) may be floor edges: nearer, a wall misread would be hit
  // before the robot sees it again (corridor-7's walls, lit in pools, near the floor's grey).
  double floor_edge_min_range_m = 1.8;
  // Wall lines (a brick wall's mortar): the frame is cut into bands of wall_line_band_columns
  // columns; in each, the rows' mean grey minus its running mean over 2 x wall_line_detrend_rows + 1
  // rows is a line profile. A band is lined when that profile's spread is at least
  // wall_line_min_std grey levels and its normalised autocorrelation reaches
  // wall_line_min_correlation at some lag in [wall_line_min_lag, wall_line_max_lag] rows
  // (horizontal lines repeating down the frame: courses of bricks; a floor seen in perspective or a
  // plain wall has no such period). WallLineFraction() is the fraction of lined bands.
  int wall_line_band_columns = 8;
  int wall_line_detrend_rows = 3;
  double wall_line_min_std = 2.0;
  double wall_line_min_correlation = 0.5;
  int wall_line_min_lag = 3;
  int wall_line_max_lag = 14;
  std::string Validate() const;  // empty when valid
};

// What a column shows.
enum class SonarReturn : std::uint8_t {
  kBoundary,     // floor from the bottom row up to a step: something stands at range_m
  kBlockedNear,  // no floor step below the horizon: the column is filled by something nearer
                 // than the bottom row's floor range (the camera's near blind zone), range_m = 0
  kFar,          // floor up to the horizon or beyond max_range_m: range_m = max_range_m
  kUnknown,      // no step, but the bottom rows look like this frame's floor: a far boundary
                 // without contrast, or something floor-like; no information (range_m = max)
};

struct SonarColumn {
  double bearing_rad = 0.0;  // left positive, robot frame
  double range_m = 0.0;      // from the robot's rotation centre (the camera foot) on the floor
  SonarReturn kind = SonarReturn::kFar;
  int boundary_row = -1;     // the lowest non-floor row when this column's own step gave the range, else -1
  double floor_edge_m = 0.0; // > 0: the range of a floor-material edge this column's floor crossed (same conditions)
  // This column's own reading before the median across columns: 0 blocked near, max_range_m
  // far or unknown, else its own step's range. A thin thing (a chair leg) the median votes out
  // still shows here.
  double own_range_m = 0.0;
};

class VisualSonar {
 public:
  // `camera`: the model at the sonar frame's size (e.g. CameraModel::Scaled(64, 48)). Throws
  // squint::Error when the camera or the options are invalid or the horizon is not in view.
  explicit VisualSonar(const CameraModel& camera, const VisualSonarOptions& options = {});

  // One frame of the camera's size; returns one entry per column (left to right). Allocates
  // nothing after construction.
  const std::vector<SonarColumn>& Process(GrayView image);

  const CameraModel& Camera() const { return camera_; }
  const VisualSonarOptions& Options() const { return options_; }
  // Floor range of the bottom row's centre: nothing nearer is seen in one frame.
  double NearBlindRangeM() const { return near_blind_m_; }
  // Floor range and bearing of the boundary between rows v and v + 1 in column u.
  double RangeAt(int u, int v) const { return range_[static_cast<std::size_t>(v * camera_.width + u)]; }
  // Fraction of the last frame's column bands showing periodic horizontal lines (see the
  // wall_line_* options): near 1 for a brick wall filling the view.
  double WallLineFraction() const { return wall_line_fraction_; }
  // The last frame's grey level per column (no averaging across columns), the mean of its rows
  // above the horizon: what stands up through the camera's height (walls, their corners and
  // edges), never the floor.
  const std::vector<float>& HorizonProfile() const { return horizon_profile_; }

 private:
  // The lowest row above `base` where something other than the region starting at `base` begins
  // (the step test of Process), or -1 when none below top_row_.
  int FindStep(int base) const;
  void MeasureWallLines(GrayView image);

  CameraModel camera_;
  VisualSonarOptions options_;
  int top_row_ = 0;  // highest row searched (one above the horizon)
  double near_blind_m_ = 0.0;
  std::vector<double> range_;    // per (u, v): range of the floor point at row v + 0.5
  std::vector<double> bearing_;  // per column
  std::vector<float> profile_;   // one column, smoothed
  std::vector<SonarColumn> out_;
  std::vector<double> raw_;     // per column before the median
  std::vector<int> rows_;
  std::vector<double> window_;
  std::vector<float> bottom_;      // per column: mean of the bottom rows
  std::vector<float> top_;         // per column: mean of the two rows below the horizon
  std::vector<float> ref_window_;
  std::vector<std::uint8_t> unknown_;
  std::vector<double> edge_;       // per column: floor-edge range crossed (0: none)
  int reference_floor_rows_ = 5;
  std::vector<double> band_rows_;   // one band's row means
  std::vector<double> line_;        // one band's detrended line profile
  double wall_line_fraction_ = 0.0;
  std::vector<float> horizon_profile_;
};

}  // namespace squint::explore
