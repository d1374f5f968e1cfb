// IPT obstacle pipeline timing: one 256×192 frame pair, whole pipeline (tracking, robust F, floor
// back-projection, classification), per detector: ipt_*_ms for an isolated pair (both frames
// detected), ipt_*_stream_ms for steady-state streaming (each frame detected once). The pair is synthetic: a textured floor and a
// box rendered by inverse perspective for two camera poses 31 mm apart (no shared data needed).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "squint/obstacles/ipt_pipeline.hpp"
#include "../tests/obstacles/obstacle_camera.hpp"

namespace {

using squint::CameraModel;
using squint::Pose2;
namespace ob = squint::obstacles;

// A random blob texture; the floor is textured in world coordinates (5 mm per texel) and the
// wall/box faces by their own coordinates, so both frames see the same scene. The texel-scale
// component is mild (0–15 grey levels) and each rendered frame gets its own sensor noise (σ = 2),
// as data-set frames do. OpenCV's SIFT with its doubled first octave finds 377 keypoints on the
// earlier frame (data-set frames: 170–290), so the pair is a somewhat busy one. The pipeline runs with
// default IptOptions, exactly as `squint obstacles` does. Rendering and the pipeline's construction (zone simulation)
// happen before the timed loop.
cv::Mat Texture(unsigned seed) {
  cv::Mat t(512, 512, CV_8U);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> v(0, 255);
  cv::Mat small(64, 64, CV_8U);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 64; ++c) small.at<unsigned char>(r, c) = static_cast<unsigned char>(v(rng));
  cv::resize(small, t, t.size(), 0, 0, cv::INTER_CUBIC);
  cv::Mat fine(512, 512, CV_8U);
  cv::randu(fine, 0, 15);
  t = t * 0.8 + fine;
  return t;
}

// Renders the view from world_T_robot: floor z = 0 and a vertical plane (box front) at x = 2.0 m
// for |y| < 0.3, z < 0.5.
cv::Mat Render(const CameraModel& cam, const Pose2& world_T_robot, const cv::Mat& floor_tex, const cv::Mat& box_tex) {
  cv::Mat img(cam.height, cam.width, CV_8U, cv::Scalar(90));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
      const Eigen::Vector2d dir = Eigen::Rotation2Dd(world_T_robot.yaw) * d.head<2>();
      const Eigen::Vector3d o(world_T_robot.x, world_T_robot.y, cam.height_m);
      const Eigen::Vector3d dw(dir.x(), dir.y(), d.z());
      double best = 1e9;
      unsigned char value = 90;
      if (dw.x() > 1e-9) {  // box front plane x = 2.0
        const double t = (2.0 - o.x()) / dw.x();
        const Eigen::Vector3d p = o + t * dw;
        if (t > 0 && std::abs(p.y()) < 0.3 && p.z() > 0 && p.z() < 0.5) {
          best = t;
          const int tx = static_cast<int>((p.y() + 0.3) / 0.6 * 511), ty = static_cast<int>(p.z() / 0.5 * 511);
          value = box_tex.at<unsigned char>(std::clamp(ty, 0, 511), std::clamp(tx, 0, 511));
        }
      }
      if (dw.z() < -1e-9) {
        const double t = o.z() / -dw.z();
        if (t < best) {
          const Eigen::Vector3d p = o + t * dw;
          const int tx = static_cast<int>(std::floor(p.x() / 0.005)) & 511, ty = static_cast<int>(std::floor(p.y() / 0.005)) & 511;
          value = floor_tex.at<unsigned char>(ty, tx);
        }
      }
      img.at<unsigned char>(v, u) = value;
    }
  return img;
}

struct Pair {
  cv::Mat a, b;
  Pose2 pa{0.0, 0.0, 0.0}, pb{0.031, 0.0, 0.0};
};

const Pair& BenchPair() {
  static const Pair pair = [] {
    Pair p;
    const CameraModel cam = squint::obstacles::testing::SimObstacleCamera();
    const cv::Mat floor_tex = Texture(1), box_tex = Texture(2);
    p.a = Render(cam, p.pa, floor_tex, box_tex);
    p.b = Render(cam, p.pb, floor_tex, box_tex);
    // Independent sensor noise in each frame (σ = 2 grey levels, fixed seed).
    cv::RNG rng(7);
    for (cv::Mat* m : {&p.a, &p.b}) {
      cv::Mat noise(m->size(), CV_16S);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, 2.0);
      cv::Mat wide;
      m->convertTo(wide, CV_16S);
      wide += noise;
      wide.convertTo(*m, CV_8U);
    }
    return p;
  }();
  return pair;
}

void RunPipeline(benchmark::State& state, ob::Detector detector) {
  const Pair& pair = BenchPair();
  ob::IptOptions options;
  options.features.detector = detector;
  ob::IptPipeline pipeline(squint::obstacles::testing::SimObstacleCamera(), options);
  ob::PairResult result;
  cv::setNumThreads(1);  // the budget is one core (DESIGN.md)
  for (auto _ : state) {
    pipeline.Process(pair.a, pair.b, pair.pa, pair.pb, &result);
    benchmark::DoNotOptimize(result.features.data());
  }
  state.counters["classified"] = benchmark::Counter(static_cast<double>(result.features.size()));
  state.counters["matches"] = benchmark::Counter(static_cast<double>(result.matches));
}

// Steady-state streaming: consecutive calls share a frame (the later frame of one pair is the earlier
// frame of the next), so the tracker reuses that frame's detection. The pairs alternate a→b, b→a
// (driving back and forth 31 mm), so every call detects exactly one new frame, as in a sequence.
void RunStream(benchmark::State& state, ob::Detector detector) {
  const Pair& pair = BenchPair();
  ob::IptOptions options;
  options.features.detector = detector;
  ob::IptPipeline pipeline(squint::obstacles::testing::SimObstacleCamera(), options);
  ob::PairResult result;
  cv::setNumThreads(1);
  pipeline.Process(pair.b, pair.a, pair.pb, pair.pa, &result);  // warm: a is now the last later frame
  bool forward = true;
  for (auto _ : state) {
    if (forward)
      pipeline.Process(pair.a, pair.b, pair.pa, pair.pb, &result);
    else
      pipeline.Process(pair.b, pair.a, pair.pb, pair.pa, &result);
    forward = !forward;
    benchmark::DoNotOptimize(result.features.data());
  }
  state.counters["classified"] = benchmark::Counter(static_cast<double>(result.features.size()));
}

void BM_IptSift(benchmark::State& state) { RunPipeline(state, ob::Detector::kSift); }
void BM_IptOrb(benchmark::State& state) { RunPipeline(state, ob::Detector::kOrb); }
void BM_IptAkaze(benchmark::State& state) { RunPipeline(state, ob::Detector::kAkaze); }
void BM_IptKlt(benchmark::State& state) { RunPipeline(state, ob::Detector::kKlt); }
void BM_IptSiftStream(benchmark::State& state) { RunStream(state, ob::Detector::kSift); }
void BM_IptOrbStream(benchmark::State& state) { RunStream(state, ob::Detector::kOrb); }
void BM_IptKltStream(benchmark::State& state) { RunStream(state, ob::Detector::kKlt); }

}  // namespace

BENCHMARK(BM_IptSift)->Name("ipt_sift_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptOrb)->Name("ipt_orb_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptAkaze)->Name("ipt_akaze_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptKlt)->Name("ipt_klt_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptSiftStream)->Name("ipt_sift_stream_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptOrbStream)->Name("ipt_orb_stream_ms")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IptKltStream)->Name("ipt_klt_stream_ms")->Unit(benchmark::kMillisecond);
