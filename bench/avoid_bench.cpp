// Benchmark of the avoidance stage on one 256×192 frame: edge map, outline tracing, contact
// points, polar map and gap steering (key avoid_ms; DESIGN.md budget: ≤ 5 ms).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "../tests/obstacles/obstacle_camera.hpp"
#include "squint/obstacles/avoider.hpp"

namespace {

using squint::obstacles::ClassifiedFeature;
using squint::obstacles::FeatureClass;

// A textured floor (tiles + noise) with six dark boxes, 150 obstacle features on and around
// their borders and 150 ground features: a busy scene, heavier than the data sets' frames.
struct Scene {
  cv::Mat image;
  std::vector<ClassifiedFeature> features;
};

Scene MakeScene() {
  Scene s;
  s.image.create(192, 256, CV_8U);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 4.0);
  for (int v = 0; v < 192; ++v)
    for (int u = 0; u < 256; ++u) {
      const int tile = ((u / 24) + (v / 16)) % 2;
      s.image.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(140 + 25 * tile + noise(rng));
    }
  std::uniform_real_distribution<double> jitter(-3.0, 3.0);
  for (int k = 0; k < 6; ++k) {
    const int u0 = 10 + 40 * k, u1 = u0 + 24, v0 = 60 + 5 * k, v1 = 120 + 8 * k;
    cv::rectangle(s.image, cv::Rect(u0, v0, u1 - u0, v1 - v0), cv::Scalar(40 + 10 * k), cv::FILLED);
    for (int j = 0; j < 25; ++j) {
      ClassifiedFeature f;
      f.pixel = {(j % 2 ? u0 : u1) + jitter(rng), v0 + (v1 - v0) * (j / 25.0)};
      f.previous_pixel = f.pixel;
      f.discrepancy_m = 0.1;
      f.cls = FeatureClass::kObstacle;
      s.features.push_back(f);
    }
  }
  std::uniform_real_distribution<double> uu(0.0, 255.0), vv(130.0, 191.0);
  for (int j = 0; j < 150; ++j) {
    ClassifiedFeature f;
    f.pixel = {uu(rng), vv(rng)};
    f.previous_pixel = f.pixel;
    f.discrepancy_m = 0.005;
    f.cls = FeatureClass::kGround;
    s.features.push_back(f);
  }
  return s;
}

void BM_Avoid(benchmark::State& state) {
  const Scene scene = MakeScene();
  squint::obstacles::Avoider avoider(squint::obstacles::testing::ObstacleCamera());
  avoider.Process(scene.image, scene.features);  // warm the buffers
  for (auto _ : state) {
    const auto& r = avoider.Process(scene.image, scene.features);
    benchmark::DoNotOptimize(r.decision.stop);
    benchmark::DoNotOptimize(r.contacts.data());
  }
  state.counters["contacts"] = static_cast<double>(avoider.Result().contacts.size());
}
BENCHMARK(BM_Avoid)->Name("avoid_ms")->Unit(benchmark::kMillisecond);

}  // namespace
