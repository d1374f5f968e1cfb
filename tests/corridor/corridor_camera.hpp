// The 160×120 camera (fx 170 px, 0.7 m high, level) of the corridor perception tests built on
// full-resolution synthetic frames (perceiver_test.cpp, heading_fusion_test.cpp).
#pragma once

#include "squint/core/camera.hpp"

namespace squint::corridor::testing {

inline CameraModel Camera160() {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 170.0;
  c.cx = 79.5;
  c.cy = 59.5;
  c.height_m = 0.7;
  return c;
}

}  // namespace squint::corridor::testing
