// Closed-loop exploration speed: one control step (render the 32×24 glance, corridor perception
// with the gate, explorer, robot step) in the built-in default world; the explorer alone; and the
// visual sonar (one 64×31 cropped frame, rendered outside the loop) with its memory update; the
// walls' base lines on one cropped 128×96 frame.
#include <benchmark/benchmark.h>

#include <cmath>

#include "squint/corridor/perceiver.hpp"
#include "squint/eval/explore_run.hpp"
#include "squint/explore/explorer.hpp"
#include "squint/explore/obstacle_memory.hpp"
#include "squint/explore/visual_sonar.hpp"
#include "squint/explore/wall_lines.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/robot.hpp"
#include "squint/sim/world.hpp"

namespace {

using namespace squint;

void BM_ClosedLoopStep(benchmark::State& state) {
  const sim::World world = sim::LoadWorld("default");
  const CameraModel cam = world.camera.Model().Scaled(corridor::kGlanceWidth, corridor::kGlanceHeight);
  sim::RenderOptions ro;
  ro.supersample = 2;
  ro.noise_sigma = 2.0;
  sim::Renderer renderer(world, cam, ro);
  corridor::Perceiver perceiver({}, cam);
  sim::Robot robot(world, world.start);
  explore::Explorer explorer;
  corridor::Glance glance;
  MutableGrayView view{glance.pixels.data(), corridor::kGlanceWidth, corridor::kGlanceHeight, corridor::kGlanceWidth};
  Pose2 prev = robot.OdomPose();
  std::uint64_t frame = 0;
  for (auto _ : state) {
    renderer.Render(robot.TruePose(), view, nullptr, 0, nullptr, 0, frame);
    const Pose2 odom = robot.OdomPose();
    if (explorer.TakeGateReset() || explorer.WantsFullProcessing()) perceiver.ResetGateReference();
    const corridor::PerceptionResult r = perceiver.ProcessGlance(glance, Between(prev, odom).x, 1.0 / 30.0);
    prev = odom;
    explore::Percept p;
    p.stamp_s = static_cast<double>(frame) / 30.0;
    p.odom_T_robot = odom;
    p.processed = r.processed;
    p.heading_deg = r.heading_deg;
    p.dist_end_m = r.dist_end_m;
    p.centre_heading_deg = r.Heading(corridor::HeadingCue::kSymmetry).heading_deg;
    p.glance_entropy_nats = r.entropy;
    const explore::Command c = explorer.Step(p);
    benchmark::DoNotOptimize(robot.Step(c.v_mps, c.omega_rps));
    ++frame;
  }
}
BENCHMARK(BM_ClosedLoopStep)->Name("closed_loop_step_us")->Unit(benchmark::kMicrosecond);

void BM_ExplorerStep(benchmark::State& state) {
  explore::Explorer explorer;
  explore::Percept p;
  p.processed = true;
  p.heading_deg = 1.0;
  p.centre_heading_deg = 2.0;
  p.dist_end_m = 20.0;
  p.glance_entropy_nats = 3.2;
  double t = 0.0;
  for (auto _ : state) {
    p.stamp_s = t;
    t += 1.0 / 30.0;
    benchmark::DoNotOptimize(explorer.Step(p));
  }
}
BENCHMARK(BM_ExplorerStep)->Name("explorer_step_us")->Unit(benchmark::kMicrosecond);

void BM_VisualSonar(benchmark::State& state) {
  const sim::World world = sim::LoadWorld("default");
  const CameraModel cam = eval::BelowHorizon(world.camera.Model().Scaled(64, 48));
  sim::RenderOptions ro;
  ro.noise_sigma = 2.0;
  sim::Renderer renderer(world, cam, ro);
  const cv::Mat image = renderer.Render(Pose2{10.0, 0.2, 0.1});
  const GrayView view{image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step)};
  explore::VisualSonar sonar(cam);
  explore::ObstacleMemory memory;
  double t = 0.0;
  for (auto _ : state) {
    const auto& scan = sonar.Process(view);
    memory.Update(scan, Pose2{10.0, 0.2, 0.1}, t, sonar.NearBlindRangeM());
    memory.Gather(Pose2{10.0, 0.2, 0.1}, t);
    benchmark::DoNotOptimize(memory.FreeTravel(Pose2{10.0, 0.2, 0.1}, 0.1, 0.35, 2.0));
    t += 0.1;
  }
}
BENCHMARK(BM_VisualSonar)->Name("visual_sonar_scan_us")->Unit(benchmark::kMicrosecond);

// The walls' base lines on the loop's 128×96 frame (cropped from a little above the horizon, as
// the runner renders it) in corridor-2's carpeted corridor, rendered outside the loop.
void BM_WallLines(benchmark::State& state) {
  const sim::World world = sim::LoadWorld("corridor-2");
  const CameraModel cam = eval::BelowHorizon(world.camera.Model().Scaled(128, 96));
  sim::RenderOptions ro;
  ro.noise_sigma = 1.0;
  sim::Renderer renderer(world, cam, ro);
  const cv::Mat image = renderer.Render(Pose2{8.0, 0.3, 0.15});
  const GrayView view{image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step)};
  for (auto _ : state) benchmark::DoNotOptimize(explore::FindWallLines(view, cam));
}
BENCHMARK(BM_WallLines)->Name("wall_lines_us")->Unit(benchmark::kMicrosecond);

}  // namespace
