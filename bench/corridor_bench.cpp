// Corridor perception timings: glance_full_us (all eight measures and fusion on one glance,
// consecutive-frame measures included), gate_us (the rapid-perception decision on a glance), and
// the parts of a glance: glance_prepare_us (levels and Sobel) and glance_<cue>_us per heading cue.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/corridor/floor_contact.hpp"
#include "squint/corridor/heading_measures.hpp"
#include "squint/corridor/perceiver.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace {

using namespace squint::corridor;

// A synthetic 160×120 corridor-like frame: a bright far wall, darker side walls converging on a
// vanishing point, ceiling lights, plus a little deterministic texture; `shift` moves it sideways.
std::vector<std::uint8_t> SyntheticFrame(int shift) {
  constexpr int w = 160, h = 120;
  std::vector<std::uint8_t> img(w * h);
  const double vx = 80.0 + shift, vy = 55.0;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double dx = u - vx, dy = v - vy;
      double val;
      if (std::abs(dx) < 12 && std::abs(dy) < 10) val = 200;                   // end wall
      else if (std::abs(dy) > 0.6 * std::abs(dx)) val = dy < 0 ? 150 : 110;   // ceiling / floor
      else val = 70 + 20 * std::sin(0.3 * dx);                                  // side walls
      if (dy < -20 && std::abs(dx) < 4) val = 250;                             // lights
      val += ((u * 7 + v * 13) % 11) - 5;
      img[v * w + u] = static_cast<std::uint8_t>(std::clamp(val, 0.0, 255.0));
    }
  }
  return img;
}

squint::CameraModel Camera() {
  squint::CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 170.0;
  c.cx = 79.5;
  c.cy = 59.5;
  c.height_m = 0.7;
  c.pitch_deg = -3.0;
  return c;
}

void BM_GlanceFull(benchmark::State& state) {
  CorridorOptions options;
  options.gate.enabled = false;
  options.distance.speed_mps = 0.4;
  // All eight measures run: cues whose default weight is 0 (entropy) are not computed by default,
  // so they get a weight here.
  for (HeadingCueOptions& cue : options.heading.cues)
    if (cue.weight <= 0.0) cue.weight = 1.0;
  Perceiver perceiver(options, Camera());
  const auto a = SyntheticFrame(0), b = SyntheticFrame(2);
  Glance ga, gb;
  MakeGlance(squint::GrayView{a.data(), 160, 120, 160}, GlanceSampling::kPoint, ga);
  MakeGlance(squint::GrayView{b.data(), 160, 120, 160}, GlanceSampling::kPoint, gb);
  bool flip = false;
  for (auto _ : state) {
    PerceptionResult r = perceiver.ProcessGlance(flip ? ga : gb, 0.1, 0.25);
    benchmark::DoNotOptimize(r);
    flip = !flip;
  }
}
BENCHMARK(BM_GlanceFull)->Name("glance_full_us")->Unit(benchmark::kMicrosecond);

// The end wall's floor contact on one 160×120 frame (every frame Process() is given, with a full
// camera): the centre columns' edges below the horizon and their floor distances.
void BM_FloorContact(benchmark::State& state) {
  FloorContact fc(Camera(), FloorContactOptions{});
  const auto a = SyntheticFrame(0);
  const squint::corridor::PixelView view{a.data(), 160, 120, 160, 1};
  for (auto _ : state) {
    std::optional<double> d = fc.Measure(view);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_FloorContact)->Name("floor_contact_us")->Unit(benchmark::kMicrosecond);

// Full frame → glance → whole-glance entropy → decision: what every frame costs when skipped.
void BM_GlanceFromFrame(benchmark::State& state) {
  const auto a = SyntheticFrame(0);
  Glance g;
  for (auto _ : state) {
    MakeGlance(squint::GrayView{a.data(), 160, 120, 160}, GlanceSampling::kPoint, g);
    benchmark::DoNotOptimize(g);
  }
}
BENCHMARK(BM_GlanceFromFrame)->Name("glance_sample_us")->Unit(benchmark::kMicrosecond);

void BM_Gate(benchmark::State& state) {
  const auto a = SyntheticFrame(0), b = SyntheticFrame(1);
  Glance ga, gb;
  MakeGlance(squint::GrayView{a.data(), 160, 120, 160}, GlanceSampling::kPoint, ga);
  MakeGlance(squint::GrayView{b.data(), 160, 120, 160}, GlanceSampling::kPoint, gb);
  RapidPerceptionGate gate;
  PreparedGlance prepared;
  bool flip = false;
  for (auto _ : state) {
    ComputeHistogramAndEntropy(flip ? ga : gb, 6, prepared);
    const bool process = gate.Update(prepared.entropy);
    benchmark::DoNotOptimize(process);
    flip = !flip;
  }
}
BENCHMARK(BM_Gate)->Name("gate_us")->Unit(benchmark::kMicrosecond);

// One heading cue on a prepared glance, with the benchmark camera's horizon (as the Perceiver).
void BM_HeadingCue(benchmark::State& state, HeadingCue cue) {
  const HeadingOptions options;
  const auto frame = SyntheticFrame(0);
  Glance g;
  MakeGlance(squint::GrayView{frame.data(), 160, 120, 160}, GlanceSampling::kPoint, g);
  PreparedGlance prepared;
  ComputeHistogramAndEntropy(g, 6, prepared);
  PrepareMeasures(options.column_bits, options.vanishing_bits, prepared);
  const auto measure = MakeHeadingMeasure(cue, options, Camera().Scaled(kGlanceWidth, kGlanceHeight).HorizonRow());
  HeadingMeasureResult r;
  for (auto _ : state) {
    measure->Measure(prepared, r);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK_CAPTURE(BM_HeadingCue, entropy, HeadingCue::kEntropy)->Name("glance_entropy_us")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_HeadingCue, symmetry, HeadingCue::kSymmetry)->Name("glance_symmetry_us")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_HeadingCue, phase, HeadingCue::kPhase)->Name("glance_phase_us")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_HeadingCue, vanishing, HeadingCue::kVanishing)->Name("glance_vanishing_us")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_HeadingCue, bright, HeadingCue::kBright)->Name("glance_bright_us")->Unit(benchmark::kMicrosecond);

// The per-glance quantities the measures share (quantised levels, Sobel gradients).
void BM_PrepareMeasures(benchmark::State& state) {
  const HeadingOptions options;
  const auto frame = SyntheticFrame(0);
  Glance g;
  MakeGlance(squint::GrayView{frame.data(), 160, 120, 160}, GlanceSampling::kPoint, g);
  PreparedGlance prepared;
  ComputeHistogramAndEntropy(g, 6, prepared);
  for (auto _ : state) {
    PrepareMeasures(options.column_bits, options.vanishing_bits, prepared);
    benchmark::DoNotOptimize(prepared);
  }
}
BENCHMARK(BM_PrepareMeasures)->Name("glance_prepare_us")->Unit(benchmark::kMicrosecond);

}  // namespace
