// The Perceiver: gate behaviour (§5.3), degenerate frames, fusion of a known corridor, and no
// heap allocation per glance in steady state (counted by replacing operator new in this binary).
#include "corridor_camera.hpp"
#include "squint/corridor/perceiver.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace squint::corridor {
namespace {

using testing::Camera160;

// A 160×120 frame of the radial corridor pattern (see heading_measures_test) with its vanishing
// point at full-resolution pixel (vx, vy), ceiling lights on the axis, and a tiny per-frame offset.
std::vector<std::uint8_t> Frame(double vx, double vy, int variant = 0) {
  std::vector<std::uint8_t> img(160 * 120);
  for (int v = 0; v < 120; ++v) {
    for (int u = 0; u < 160; ++u) {
      const double theta = std::atan2(v - vy, u - vx);
      double value = 100.0 + 60.0 * std::cos(6 * theta) + variant;
      if (v < 45 && std::abs(u - vx) < 3 && (v / 8) % 2 == 0) value = 255;  // ceiling lights
      img[v * 160 + u] = static_cast<std::uint8_t>(std::clamp(value, 0.0, 255.0));
    }
  }
  return img;
}

GrayView View(const std::vector<std::uint8_t>& img) { return {img.data(), 160, 120, 160}; }

void ExpectFinite(const PerceptionResult& r) {
  if (r.heading_deg) {
    EXPECT_TRUE(std::isfinite(*r.heading_deg));
  }
  if (r.dist_end_m) {
    EXPECT_TRUE(std::isfinite(*r.dist_end_m));
  }
  for (const auto& h : r.heading) {
    if (h.heading_deg) {
      EXPECT_TRUE(std::isfinite(*h.heading_deg));
    }
    if (h.column_px) {
      EXPECT_TRUE(std::isfinite(*h.column_px));
    }
    for (float c : h.curve) EXPECT_TRUE(std::isfinite(c));
    EXPECT_EQ(h.HasEstimate(), h.reason == Reason::kNone);
  }
  for (const auto& d : r.distance) {
    if (d.dist_m) {
      EXPECT_TRUE(std::isfinite(*d.dist_m));
    }
    if (d.raw) {
      EXPECT_TRUE(std::isfinite(*d.raw));
    }
    EXPECT_EQ(d.HasEstimate(), d.reason == Reason::kNone);
  }
}

TEST(Perceiver, FusedHeadingOfAKnownCorridor) {
  CorridorOptions options;
  options.gate.enabled = false;
  Perceiver perceiver(options, Camera160());
  // Vanishing point 22.5 px right of centre at full resolution (u = 102, the pixel that glance
  // column 20 samples; the symmetry cue scores whole-column axes): heading = atan(22.5 / 170),
  // left positive.
  const auto img = Frame(102.0, 59.5);
  const PerceptionResult r = perceiver.Process(View(img), std::nullopt, 0.1);
  ExpectFinite(r);
  ASSERT_TRUE(r.processed);
  ASSERT_TRUE(r.heading_deg.has_value());
  const double expected = RadToDeg(std::atan(22.5 / 170.0));
  // One glance column is 5 px at full resolution: atan(5 / 170) ≈ 1.7°.
  EXPECT_NEAR(*r.heading_deg, expected, RadToDeg(std::atan(5.0 / 170.0)));
  EXPECT_GT(expected, 0.0);
}

TEST(Perceiver, UniformFrameGivesNoEstimateWithReasons) {
  CorridorOptions options;
  options.gate.enabled = false;
  Perceiver perceiver(options, Camera160());
  std::vector<std::uint8_t> flat(160 * 120, 128);
  for (int i = 0; i < 3; ++i) {
    const PerceptionResult r = perceiver.Process(View(flat), 0.1, 0.1);
    ExpectFinite(r);
    EXPECT_TRUE(r.processed);
    EXPECT_FALSE(r.heading_deg.has_value());
    EXPECT_FALSE(r.dist_end_m.has_value());
    for (const auto& h : r.heading) EXPECT_NE(h.reason, Reason::kNone);
    for (const auto& d : r.distance)
      EXPECT_EQ(d.reason, i == 0 ? Reason::kNoPreviousFrame : Reason::kIdenticalFrames);
  }
}

TEST(Perceiver, GateSkipsSmallChangesAndResets) {
  CorridorOptions paper;
  paper.gate.threshold = 0.01;  // the paper's threshold (the default, 0.05, wants a larger change)
  Perceiver perceiver(paper, Camera160());
  const auto a = Frame(90.0, 59.5);
  const auto far = Frame(40.0, 40.0, 30);
  PerceptionResult r = perceiver.Process(View(a), std::nullopt, 0.1);
  EXPECT_TRUE(r.processed);  // first frame: the reference
  EXPECT_FALSE(r.gate_change.has_value());
  r = perceiver.Process(View(a), std::nullopt, 0.1);
  EXPECT_FALSE(r.processed);  // no change
  ASSERT_TRUE(r.gate_change.has_value());
  EXPECT_EQ(*r.gate_change, 0.0);
  EXPECT_FALSE(r.heading_deg.has_value());
  for (const auto& h : r.heading) EXPECT_EQ(h.reason, Reason::kNotProcessed);
  r = perceiver.Process(View(far), std::nullopt, 0.1);
  EXPECT_TRUE(r.processed);  // a large change
  EXPECT_GE(*r.gate_change, 0.01);
  perceiver.ResetGateReference();
  r = perceiver.Process(View(far), std::nullopt, 0.1);
  EXPECT_TRUE(r.processed);  // the new corridor's first frame
}

TEST(Perceiver, RejectsInvalidOptions) {
  CorridorOptions options;
  options.heading.cues[1].weight = -1.0;
  EXPECT_THROW(Perceiver p(options), Error);
  options = {};
  options.distance.max_m = -1.0;
  EXPECT_FALSE(options.Validate().empty());
  options = {};
  options.heading.min_consensus_cues = 0;
  EXPECT_NE(options.Validate().find("min_consensus_cues"), std::string::npos);
  options.heading.min_consensus_cues = kHeadingCueCount + 1;
  EXPECT_NE(options.Validate().find("min_consensus_cues"), std::string::npos);
  options = {};
  options.distance.ttc_cell_px = 2.0;  // 0 (off) or at least 3
  EXPECT_NE(options.Validate().find("ttc_cell_px"), std::string::npos);
  options = {};
  options.distance.ttc_cell_quantile = 1.5;
  EXPECT_NE(options.Validate().find("ttc_cell_quantile"), std::string::npos);
  options = {};
  options.distance.ttc_cell_min_expansion = -0.1;
  EXPECT_NE(options.Validate().find("ttc_cell_min_expansion"), std::string::npos);
}

TEST(Perceiver, FallbackScaleWithoutIntrinsics) {
  CorridorOptions options;
  options.gate.enabled = false;
  Perceiver perceiver(options);
  EXPECT_NEAR(perceiver.ColumnToHeadingDeg(15.5), 0.0, 1e-12);
  EXPECT_NEAR(perceiver.ColumnToHeadingDeg(25.5), 10.0 * options.heading.fallback_deg_per_column, 1e-12);
}

TEST(Perceiver, NoHeapAllocationPerGlanceInSteadyState) {
  // Also with the heading filter, the far-structure cells, time to contact's own finer image and
  // the floor contact's motion test and same-sign refinement (calibrated options).
  for (const bool filter : {false, true}) {
    CorridorOptions options;
    options.gate.enabled = false;
    options.distance.speed_mps = 0.4;
    options.heading.filter.enabled = filter;
    if (filter) options.distance.ttc_cell_px = 6.0;
    if (filter) options.distance.ttc_glance_scale = 2.0;  // time to contact's own 64×48 image
    if (filter) options.distance.floor_contact.motion_window_m = 2.0;
    if (filter) options.distance.floor_contact.refine_same_sign = true;
    Perceiver perceiver(options, Camera160());
    const auto a = Frame(85.0, 59.5), b = Frame(86.0, 59.5, 4);
    perceiver.Process(View(a), std::nullopt, 0.1);  // warm-up: tables built once
    perceiver.Process(View(b), std::nullopt, 0.1);
    const long before = g_allocations.load();
    for (int i = 0; i < 20; ++i) {
      const PerceptionResult r = perceiver.Process(View(i % 2 ? a : b), std::nullopt, 0.1, 1.0);
      ASSERT_TRUE(r.processed);
      EXPECT_EQ(r.heading_deg.has_value(), filter || r.heading_instant_deg.has_value());
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "filter " << filter;
  }
}

}  // namespace
}  // namespace squint::corridor
