// Simulator rendering speed: 32×24 glances with 4×4 supersampling in the default building, and
// 256×192 frames (one sample per pixel, label mask on) in the obstacle course.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace {

using squint::Pose2;

// Poses down the default building's south corridor and up its east corridor, turning a little.
std::vector<Pose2> DefaultPoses() {
  std::vector<Pose2> poses;
  for (int i = 0; i < 64; ++i) {
    const double yaw = 0.3 * std::sin(i * 0.7);
    if (i < 32) poses.push_back({1.0 + i * 1.2, 0.3 * std::sin(i * 0.3), yaw});
    else poses.push_back({40.0 + 0.3 * std::sin(i * 0.3), (i - 32) * 0.75, 1.5708 + yaw});
  }
  return poses;
}

void BM_RenderGlance(benchmark::State& state) {
  const squint::sim::World world = squint::sim::LoadWorld("default");
  squint::sim::RenderOptions opt;
  opt.supersample = 4;
  squint::sim::Renderer renderer(world, world.camera.Model().Scaled(32, 24), opt);
  std::vector<std::uint8_t> image(32 * 24);
  const std::vector<Pose2> poses = DefaultPoses();
  std::size_t i = 0;
  for (auto _ : state) {
    renderer.Render(poses[i % poses.size()], {image.data(), 32, 24, 32}, nullptr, 0, nullptr, 0, i);
    ++i;
    benchmark::DoNotOptimize(image.data());
  }
}
BENCHMARK(BM_RenderGlance)->Name("render_glance_per_s")->Unit(benchmark::kMicrosecond);

void BM_Render256(benchmark::State& state) {
  const squint::sim::World world = squint::sim::LoadWorld("obstacle-course");
  squint::sim::RenderOptions opt;
  opt.supersample = 1;
  squint::sim::Renderer renderer(world, world.camera.Model().Scaled(256, 192), opt);
  std::vector<std::uint8_t> image(256 * 192), label(256 * 192);
  std::vector<Pose2> poses;
  for (int k = 0; k < 32; ++k) poses.push_back({1.0 + k * 0.35, 0.8 * std::sin(k * 0.4), 0.25 * std::sin(k * 0.9)});
  std::size_t i = 0;
  for (auto _ : state) {
    renderer.Render(poses[i % poses.size()], {image.data(), 256, 192, 256}, label.data(), 256, nullptr, 0, i);
    ++i;
    benchmark::DoNotOptimize(image.data());
    benchmark::DoNotOptimize(label.data());
  }
}
BENCHMARK(BM_Render256)->Name("render_256x192_per_s")->Unit(benchmark::kMicrosecond);

}  // namespace
