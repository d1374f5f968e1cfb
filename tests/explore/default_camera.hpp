// The default world's camera (0.6 m high, pitched 3° down, 60° wide) at a given size, for the
// explore module's tests on constructed frames (visual_sonar_test.cpp, light_line_test.cpp).
#pragma once

#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/camera.hpp"

namespace squint::explore::testing {

inline CameraModel DefaultWorldCamera(int width, int height) {
  CameraModel c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width / std::tan(DegToRad(30.0));
  c.cx = 0.5 * width - 0.5;
  c.cy = 0.5 * height - 0.5;
  c.height_m = 0.6;
  c.pitch_deg = -3.0;
  return c;
}

}  // namespace squint::explore::testing
