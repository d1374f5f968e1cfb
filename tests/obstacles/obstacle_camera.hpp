// The obstacle cameras shared by the obstacle tests and benchmarks: the one of
// ../shared/data/obstacles-* (256×192, 0.43 m high, pitched −9°, obstacle paper §6.1) and the
// simulator's version of it with a round focal length.
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

// The same mount with fx = fy = 200 px, as the simulator's obstacle worlds render it
// (tests/obstacles/ipt_pipeline_test.cpp, bench/obstacles_bench.cpp).
inline CameraModel SimObstacleCamera() {
  CameraModel c = ObstacleCamera();
  c.fx = c.fy = 200.0;
  return c;
}

}  // namespace squint::obstacles::testing
