// The walls' base lines from where the floor's texture ends, in a camera frame of modest size
// (128×96): the corridor's direction, and the robot's place across it, where the walls have the
// floor's grey.
//
// The visual sonar reads the floor's edge by grey-level contrast, and the glance's heading cues
// scatter by 10° or more where the walls have the floor's grey (corridor-2's panels over its
// carpet, `default`'s carpeted middle corridor). What still differs there is texture: a carpet,
// tiles or speckle give every row of the floor fine vertical grey-level structure, while a painted
// or panelled wall is smooth along its columns (its seams are vertical lines, which a vertical
// second difference does not see). Each column is scanned up from the bottom for the first row
// with textured floor below it and a smooth stretch above it: the wall's base in that column,
// mapped to the floor plane by the camera model. The points of one wall lie on a line; a
// corridor's two walls on two parallel lines. A line is fitted by sampling point pairs (a fixed,
// deterministic set), scored by its own inliers plus the largest group of points on one line
// parallel to it, and refined by least squares over both groups.
//
// Measured on sweeps of the built-in worlds and of the development data (`../shared/data`,
// another renderer's images), docs/explore.md: the per-frame direction within 0.3–1.7° (median)
// in most corridors, 2–3° in corridor-2.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "squint/core/camera.hpp"
#include "squint/core/image_view.hpp"

namespace squint::explore {

struct WallLineOptions {
  int below_rows = 5;              // rows of textured floor needed just below a wall's base...
  int above_rows = 8;              // ...and rows of smooth wall looked at just above it
  double smooth_ratio = 0.35;      // the wall's mean texture below this fraction of the floor's
  double min_floor_texture = 2.0;  // grey levels: the floor's mean texture below a base at least this...
  double floor_texture_fraction = 0.5;  // ...and this fraction of the bottom rows' median texture
  double base_row_offset = 1.0;    // rows added to the base found (below positive): the first wall row also responds to the step
  int reference_rows = 6;          // bottom rows whose median texture is the floor's reference
  double max_range_m = 8.0;        // base points farther than this are not used
  double inlier_m = 0.06;          // distance of a point from its line to count as on it
  double parallel_bin_m = 0.12;    // width of the offset bins in which a parallel line is sought
  double min_pair_m = 0.3;         // sampled pairs closer than this do not define a line
  int samples = 200;               // sampled pairs
  int min_inliers = 10;            // points on the main line needed for a reading
  double min_span_m = 0.8;         // spread of the main line's points along it needed...
  int min_rows = 3;                // ...and the image rows they come from
  // Points between the two lines on neither make a foot across the corridor (WallLines::
  // corridor_ahead_m) only this many together: a textured floor's own edges (tile joints, a
  // carpet's blotches) give up to about 13 within 2.5 m in `default`'s middle corridor, an end
  // wall's foot one per column across it.
  int foot_points = 16;
  // A best line whose points come from fewer than min_rows image rows (a far foot across the view,
  // an end wall's) is left out with its points and the lines sought once more among the rest: a
  // near wall's base beside it has fewer points but a direction (corridor-2, 0.35 m from its wall,
  // the end wall 7 m ahead). false: such a frame has no lines.
  bool drop_one_row_line = false;
  std::string Validate() const;
};

struct WallLines {
  bool valid = false;
  int points = 0;              // base points found (within max_range_m)
  int inliers = 0;             // on the main line
  int parallel_inliers = 0;    // on the parallel line (0: none found)
  double direction_rad = 0.0;  // the lines' direction in the robot frame, in (−π/2, π/2] (left positive)
  double offset_m = 0.0;       // the main line's signed distance from the robot along its left normal
  double parallel_offset_m = 0.0;  // the parallel line's, when parallel_inliers > 0
  double rms_m = 0.0;          // RMS distance of the inliers (both lines) from the fit
  // When both lines were found with the robot between them: how far ahead (along the lines'
  // direction) a foot across the corridor between them stands (an end wall's or an obstacle's:
  // the foot_points-th nearest point there on neither line), max_range_m if none; 0 otherwise.
  // The floor's texture shows the corridor free that far, whatever its grey-level contrast.
  double corridor_ahead_m = 0.0;
  // Each column's mean texture over the frame's bottom below_rows rows (grey levels, the second
  // difference's magnitude as the base search uses it), whether or not lines were found: a column
  // whose bottom is as smooth as a wall sees something standing nearer than the floor at the
  // frame's bottom (where wall and floor have one grey, the visual sonar cannot tell).
  std::vector<float> bottom_texture;
  // The robot's heading relative to the lines modulo 90°, in [−45°, 45°), left positive:
  // −direction (a Manhattan building's walls are parallel or perpendicular to the corridor's axis).
  double HeadingDeg() const;
};

// The walls' base lines in `image`, whose camera is `camera` (same size). `base_points`, when
// given, receives the floor points found (robot frame, x forward, y left). Invalid when the floor
// shows no texture, too few points lie on one line, or they span too little of it.
WallLines FindWallLines(const GrayView& image, const CameraModel& camera, const WallLineOptions& options = {},
                        std::vector<Eigen::Vector2d>* base_points = nullptr);

}  // namespace squint::explore
