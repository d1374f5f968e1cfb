// The obstacle pipeline as `squint explore` runs it per frame pair (issue 7): ORB IPT on two
// 256×192 frames of the default world 0.24 m apart (the loop's pair at cruise speed, rendered
// outside the timing), the Avoider, and the explorer's ObstacleAdvice.
#include <benchmark/benchmark.h>

#include <cmath>

#include "squint/eval/explore_run.hpp"
#include "squint/explore/obstacle_advice.hpp"
#include "squint/obstacles/avoider.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace {

using namespace squint;

void BM_ExploreObstaclePair(benchmark::State& state) {
  const sim::World world = sim::LoadWorld("default");
  const eval::ExploreRunOptions opt;
  const CameraModel cam = world.camera.Model().Scaled(opt.ipt_width, opt.ipt_height);
  sim::RenderOptions ro;
  ro.noise_sigma = opt.sensor_noise_sigma;
  sim::Renderer renderer(world, cam, ro);
  const Pose2 a = world.start;
  const Pose2 b{a.x + 0.24 * std::cos(a.yaw), a.y + 0.24 * std::sin(a.yaw), a.yaw};
  const cv::Mat first = renderer.Render(a, nullptr, nullptr, 0);
  const cv::Mat second = renderer.Render(b, nullptr, nullptr, 1);
  obstacles::IptPipeline ipt(cam, opt.ipt);
  obstacles::AvoidOptions avoid = opt.avoid;
  avoid.gap.robot_radius_m = world.robot.radius_m;
  obstacles::Avoider avoider(cam, avoid);
  explore::ObstacleAdviceOptions advice = opt.advice;
  advice.robot_radius_m = world.robot.radius_m;
  obstacles::PairResult pair;
  for (auto _ : state) {
    ipt.Process(first, second, a, b, &pair);
    if (pair.Ok()) {
      const obstacles::AvoidResult& r = avoider.Process(second, pair.features);
      benchmark::DoNotOptimize(explore::MakeObstacleAdvice(*r.map, r.decision, advice));
    }
  }
}
BENCHMARK(BM_ExploreObstaclePair)->Name("explore_obstacle_pair_ms")->Unit(benchmark::kMillisecond);

}  // namespace
