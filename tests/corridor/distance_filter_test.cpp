// The Perceiver's distance pipeline and gate on constructed sequences: an approach to a plane
// (time to contact over a growing baseline, the temporal median with odometry, the restart when
// the robot stops) and the rapid-perception gate's reference and forced processing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "squint/corridor/perceiver.hpp"

namespace squint::corridor {
namespace {

// A smooth pattern on a plane Z metres ahead of a camera that started z0 metres away, seen
// magnified by z0 / Z about the glance point (cx, cy).
Glance PlaneAt(double z, double z0 = 12.0, double cx = 15.5, double cy = 11.5) {
  const double scale = z0 / z;
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double x = (u - cx) / scale, y = (v - cy) / scale;
      const double value = 128.0 + 50.0 * std::sin(0.31 * x + 0.17 * y) + 40.0 * std::cos(0.23 * y - 0.27 * x + 0.5);
      g.At(u, v) = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  return g;
}

CorridorOptions DistanceOnly() {
  CorridorOptions o;
  o.gate.enabled = false;
  for (auto& c : o.heading.cues) c.enabled = false;
  o.distance.enabled = {true, false, false};  // time to contact alone: its model is the identity
  return o;
}

TEST(PerceiverDistance, ApproachingAPlaneGivesTheDistanceOverALongerBaseline) {
  // No camera: the expansion centre is the glance centre (15.5, 11.5), where PlaneAt expands.
  Perceiver perceiver(DistanceOnly(), std::nullopt);
  const double step = 0.05;
  int longest = 0;
  for (int i = 0; i <= 60; ++i) {
    const double z = 12.0 - step * i;
    const PerceptionResult r = perceiver.ProcessGlance(PlaneAt(z), i == 0 ? std::nullopt : std::optional(step), 0.1);
    const DistanceMeasureResult& d = r.Distance(DistanceCue::kTimeToContact);
    longest = std::max(longest, d.baseline_frames);
    if (i < 12) continue;  // the median window fills
    ASSERT_TRUE(r.dist_end_m.has_value()) << "frame " << i << ": " << ReasonText(d.reason);
    EXPECT_NEAR(*r.dist_end_m, z, 0.05 * z) << "frame " << i;
    ASSERT_TRUE(d.filtered_input.has_value());
  }
  // One frame expands this image by 0.4 %; the baseline grows towards 10 % of the distance.
  EXPECT_GE(longest, 8);
}

TEST(PerceiverDistance, MedianRejectsAnOutlierFrameAndRestartsWhenStopped) {
  Perceiver perceiver(DistanceOnly(), std::nullopt);
  const double step = 0.05;
  std::optional<double> before;
  for (int i = 0; i <= 30; ++i) {
    const double z = 12.0 - step * i;
    Glance g = PlaneAt(z);
    if (i == 25)  // one corrupted frame (a flash): its own estimate is far off
      for (auto& p : g.pixels) p = static_cast<std::uint8_t>(255 - p);
    const PerceptionResult r = perceiver.ProcessGlance(g, i == 0 ? std::nullopt : std::optional(step), 0.1);
    if (i >= 25) {
      ASSERT_TRUE(r.dist_end_m.has_value()) << "frame " << i;
      EXPECT_NEAR(*r.dist_end_m, z, 0.05 * z) << "frame " << i;
    }
    before = r.dist_end_m;
  }
  ASSERT_TRUE(before.has_value());
  // The robot stops (odometry: no travel): the history restarts, so no time to contact until it
  // drives again and the window refills.
  PerceptionResult r = perceiver.ProcessGlance(PlaneAt(10.48), 0.0, 0.1);
  EXPECT_FALSE(r.dist_end_m.has_value());
  EXPECT_EQ(r.Distance(DistanceCue::kTimeToContact).reason, Reason::kNoTravel);
  r = perceiver.ProcessGlance(PlaneAt(10.43), step, 0.1);
  EXPECT_EQ(r.Distance(DistanceCue::kTimeToContact).baseline_frames, 1);
}

TEST(PerceiverDistance, ScaleSearchTracksAnApproachThroughGainJumps) {
  // Every other frame 15 % brighter (automatic gain): the default time to contact (the scale
  // search, NCC) tracks the approach within 5 % of the distance.
  CorridorOptions o = DistanceOnly();
  ASSERT_TRUE(o.distance.ttc_scale_search);
  const double step = 0.05;
  {
    Perceiver perceiver(o, std::nullopt);
    double sum2 = 0.0;
    int n = 0;
    for (int i = 0; i <= 60; ++i) {
      const double z = 12.0 - step * i;
      Glance g = PlaneAt(z);
      if (i % 2 == 1)
        for (auto& p : g.pixels) p = static_cast<std::uint8_t>(std::lround(std::min(255.0, 1.15 * p)));
      const PerceptionResult r = perceiver.ProcessGlance(g, i == 0 ? std::nullopt : std::optional(step), 0.1);
      if (i < 12) continue;
      const double e = r.dist_end_m ? *r.dist_end_m - z : z;  // no estimate counts as the whole distance
      sum2 += e * e;
      ++n;
    }
    EXPECT_LT(std::sqrt(sum2 / n), 0.05 * 10.0);
  }
}

// Warming up: no time-to-contact reading until the history spans ttc_warmup_m of driving, then
// readings; identical glances still say so. After a stop (restart) the median uses only the
// readings since the restart (the ring is read newest first, never a slot left from before).
TEST(PerceiverDistance, WarmUpAndRestartUseOnlyReadingsSinceTheStart) {
  CorridorOptions o = DistanceOnly();
  o.distance.ttc_warmup_m = 0.5;
  Perceiver perceiver(o, std::nullopt);
  const double step = 0.05;
  for (int i = 0; i <= 30; ++i) {
    const double z = 12.0 - step * i;
    const PerceptionResult r = perceiver.ProcessGlance(PlaneAt(z), i == 0 ? std::nullopt : std::optional(step), 0.1);
    const DistanceMeasureResult& d = r.Distance(DistanceCue::kTimeToContact);
    if (i == 0) continue;
    if (i * step < 0.5 - 1e-9) {
      EXPECT_FALSE(d.instant_m.has_value()) << "frame " << i;
      EXPECT_FALSE(r.dist_end_m.has_value()) << "frame " << i;
      EXPECT_EQ(d.reason, Reason::kNoTravel) << "frame " << i;
    } else {
      ASSERT_TRUE(d.instant_m.has_value()) << "frame " << i << ": " << ReasonText(d.reason);
      ASSERT_TRUE(r.dist_end_m.has_value()) << "frame " << i;
      EXPECT_NEAR(*r.dist_end_m, z, 0.05 * z) << "frame " << i;
    }
  }
  // Stop (no travel): the history restarts; the same glance again is "identical".
  PerceptionResult r = perceiver.ProcessGlance(PlaneAt(10.5), 0.0, 0.1);
  EXPECT_FALSE(r.dist_end_m.has_value());
  // Drive on towards a plane now 6 m away (a new scene): after the warm-up the median holds
  // only the new readings (one stale slot of the 12 m approach would be ~4 m off).
  for (int i = 1; i <= 20; ++i) {
    const double z = 6.0 - step * i;
    r = perceiver.ProcessGlance(PlaneAt(z, 6.0), step, 0.1);
    if (i * step < 0.5 - 1e-9) {
      EXPECT_FALSE(r.dist_end_m.has_value()) << "restart frame " << i;
      continue;
    }
    ASSERT_TRUE(r.dist_end_m.has_value()) << "restart frame " << i;
    EXPECT_NEAR(*r.dist_end_m, z, 0.05 * z) << "restart frame " << i;
  }
}

TEST(PerceiverDistance, FusionWeightFallsWithTheCueErrorGrowth) {
  // Two cues at different distances: with growth the nearer estimate weighs more.
  CorridorOptions o = DistanceOnly();
  o.distance.enabled = {false, true, true};
  o.distance.median_frames = 1;
  o.distance.alpha2 = 0.0;
  o.distance.beta2 = 2.0;  // Jeffrey: always 2 m
  o.distance.alpha3 = 0.0;
  // Entropy's model gives alpha3 / |ΔH|; make it answer by setting alpha3 from the frames' ΔH.
  const Glance a = PlaneAt(10.0), b = PlaneAt(9.0);
  PreparedGlance pa, pb;
  ComputeHistogramAndEntropy(a, o.distance.image_bits, pa);
  ComputeHistogramAndEntropy(b, o.distance.image_bits, pb);
  const double dh = std::abs(pa.entropy - pb.entropy);
  ASSERT_GT(dh, 0.0);
  o.distance.alpha3 = 8.0 * dh;  // entropy: 8 m
  Perceiver equal(o, std::nullopt);
  equal.ProcessGlance(a, 1.0, 0.1);
  PerceptionResult r = equal.ProcessGlance(b, 1.0, 0.1);
  ASSERT_TRUE(r.dist_end_m.has_value());
  EXPECT_NEAR(*r.dist_end_m, 5.0, 1e-9);  // equal weights: (2 + 8) / 2
  o.distance.error_growth_per_m = {0.0, 1.0, 1.0};
  Perceiver growing(o, std::nullopt);
  growing.ProcessGlance(a, 1.0, 0.1);
  r = growing.ProcessGlance(b, 1.0, 0.1);
  ASSERT_TRUE(r.dist_end_m.has_value());
  // Weights 1/3² and 1/9²: (2/9 + 8/81) / (1/9 + 1/81) = 2.6 m.
  EXPECT_NEAR(*r.dist_end_m, (2.0 / 9.0 + 8.0 / 81.0) / (1.0 / 9.0 + 1.0 / 81.0), 1e-9);
}

TEST(PerceiverDistance, UnfusedCueIsReportedNotFusedAndTooUncertainFusionGivesNone) {
  // Jeffrey reads 2 m, entropy 8 m (as above), weights 4 and 1 (σ 0.5 m and 1 m).
  CorridorOptions o = DistanceOnly();
  o.distance.enabled = {false, true, true};
  o.distance.median_frames = 1;
  o.distance.alpha2 = 0.0;
  o.distance.beta2 = 2.0;
  o.distance.weights = {1.0, 4.0, 1.0};
  const Glance a = PlaneAt(10.0), b = PlaneAt(9.0);
  PreparedGlance pa, pb;
  ComputeHistogramAndEntropy(a, o.distance.image_bits, pa);
  ComputeHistogramAndEntropy(b, o.distance.image_bits, pb);
  o.distance.alpha3 = 8.0 * std::abs(pa.entropy - pb.entropy);
  auto second = [&](const CorridorOptions& opt) {
    Perceiver p(opt, std::nullopt);
    p.ProcessGlance(a, 1.0, 0.1);
    return p.ProcessGlance(b, 1.0, 0.1);
  };
  PerceptionResult r = second(o);
  ASSERT_TRUE(r.dist_end_m.has_value());
  EXPECT_NEAR(*r.dist_end_m, (4.0 * 2.0 + 8.0) / 5.0, 1e-9);
  // Entropy not fused: still measured and reported, the fused distance is Jeffrey's.
  o.distance.fuse = {true, true, false};
  r = second(o);
  ASSERT_TRUE(r.dist_end_m.has_value());
  EXPECT_NEAR(*r.dist_end_m, 2.0, 1e-9);
  ASSERT_TRUE(r.Distance(DistanceCue::kEntropy).dist_m.has_value());
  EXPECT_NEAR(*r.Distance(DistanceCue::kEntropy).dist_m, 8.0, 1e-9);
  EXPECT_FALSE(r.Distance(DistanceCue::kEntropy).fused);
  EXPECT_TRUE(r.Distance(DistanceCue::kJeffrey).fused);
  // The fused σ is 1/sqrt(Σ w): Jeffrey alone 0.5 m, both 1/sqrt(5) = 0.447 m.
  o.distance.fused_max_std_m = 0.49;
  r = second(o);
  EXPECT_FALSE(r.dist_end_m.has_value());
  EXPECT_FALSE(r.Distance(DistanceCue::kJeffrey).fused);
  o.distance.fuse = {true, true, true};
  r = second(o);
  ASSERT_TRUE(r.dist_end_m.has_value());
  EXPECT_NEAR(*r.dist_end_m, 3.2, 1e-9);
  o.distance.fused_max_std_m = 0.44;
  EXPECT_FALSE(second(o).dist_end_m.has_value());
  o.distance.fused_max_std_m = -1.0;
  EXPECT_NE(o.Validate().find("distance.fused_max_std_m"), std::string::npos);
}

TEST(Gate, SlowDriftAccumulatesAgainstTheLastProcessedFrame) {
  // Entropy 1.000, 1.004, 1.008, ...: each step is 0.4 % of the reference.
  GateOptions paper;
  paper.threshold = 0.01;  // the paper's threshold
  paper.compare_with_last_processed = false;
  paper.max_skipped_frames = 0;
  RapidPerceptionGate previous_frame(paper);
  GateOptions accumulate = paper;
  accumulate.compare_with_last_processed = true;
  RapidPerceptionGate last_processed(accumulate);
  std::vector<bool> a, b;
  for (int i = 0; i < 10; ++i) {
    a.push_back(previous_frame.Update(1.0 + 0.004 * i));
    b.push_back(last_processed.Update(1.0 + 0.004 * i));
  }
  // Frame-to-frame the change never reaches 1 %: only the reference frame is processed.
  EXPECT_EQ(std::count(a.begin(), a.end(), true), 1);
  // Against the last processed frame the drift adds up: 0.4 %, 0.8 %, then 1.2 % >= 1 % on every
  // third frame.
  EXPECT_EQ(b, (std::vector<bool>{true, false, false, true, false, false, true, false, false, true}));
}

TEST(Gate, ProcessesAtLeastEveryNthFrame) {
  GateOptions o;
  o.max_skipped_frames = 3;
  RapidPerceptionGate gate(o);
  std::vector<bool> p;
  for (int i = 0; i < 9; ++i) p.push_back(gate.Update(2.0));  // no change at all
  EXPECT_EQ(p, (std::vector<bool>{true, false, false, false, true, false, false, false, true}));
  GateOptions bad;
  bad.max_skipped_frames = -1;
  EXPECT_FALSE(bad.Validate().empty());
}

}  // namespace
}  // namespace squint::corridor
