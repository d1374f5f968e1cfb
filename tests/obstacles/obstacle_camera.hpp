// The camera of ../shared/data/obstacles-* (256×192, 0.43 m high, pitched −9°, obstacle paper
// §6.1), shared by the obstacle tests (avoid_scene.hpp) and bench/avoid_bench.cpp.
#pragma once

#include "squint/core/camera.hpp"

namespace squint::obstacles::testing {

inline CameraModel ObstacleCamera() {
  CameraModel c;
  c.width = 256;
  c.height = 192;
  c.fx = c.fy = 194.7353;
  c.cx = 127.5;
  c.cy = 95.5;
  c.height_m = 0.43;
  c.pitch_deg = -9.0;
  return c;
}

}  // namespace squint::obstacles::testing
