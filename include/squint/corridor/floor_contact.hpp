// Distance to the end of the corridor from where the end wall stands on the floor, in the full
// camera frame (FloorContactOptions in options.hpp says how and why).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/corridor/glance.hpp"
#include "squint/corridor/options.hpp"

namespace squint::corridor {

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

  CameraModel camera_;
  FloorContactOptions options_;
  int top_row_ = 0;       // first row below the horizon
  int u_first_ = 0;       // the columns read
  int u_last_ = 0;
  std::vector<double> profile_;
  std::vector<double> readings_;
};

}  // namespace squint::corridor
