// Benchmarks of the core camera geometry used per feature by the obstacle pipeline.
#include <benchmark/benchmark.h>

#include "squint/core/camera.hpp"

namespace {

squint::CameraModel TestCamera() {
  squint::CameraModel c;
  c.width = 256;
  c.height = 192;
  c.fx = c.fy = 194.7;
  c.cx = 127.5;
  c.cy = 95.5;
  c.height_m = 0.43;
  c.pitch_deg = -9.0;
  c.distortion = {-0.1, 0.01, 0.0, 0.0, 0.0};
  return c;
}

void BM_FloorPoint(benchmark::State& state) {
  const squint::CameraModel cam = TestCamera();
  double u = 0.0;
  for (auto _ : state) {
    auto p = cam.FloorPoint({u, 150.0});
    benchmark::DoNotOptimize(p);
    u = u > 250.0 ? 0.0 : u + 1.0;
  }
}
BENCHMARK(BM_FloorPoint)->Name("camera_floor_point_us")->Unit(benchmark::kMicrosecond);

}  // namespace
