// Heading fusion in the Perceiver: the sum of the cues' normalised curves (default) follows each
// cue's calibration (scale, bias) when it resamples the curve onto the fused heading grid, the
// paper-style consensus of the cues' own estimates stays available, and the heading filter over
// time (HeadingOptions::filter) weighs the cues by their σ, follows the odometry's turn over
// skipped frames, rejects outliers and restarts after repeated rejections.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "corridor_camera.hpp"
#include "squint/corridor/perceiver.hpp"

namespace squint::corridor {
namespace {

using testing::Camera160;

// Edges radiating from the vanishing point (vx, vy) at full resolution (as corridor edges do):
// mirror-symmetric about the column through it, and every edge line passes through it.
std::vector<std::uint8_t> RadialFrame(double vx, double vy) {
  std::vector<std::uint8_t> img(160 * 120);
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u)
      img[v * 160 + u] = static_cast<std::uint8_t>(std::lround(110.0 + 80.0 * std::cos(6.0 * std::atan2(v - vy, u - vx))));
  return img;
}

// Only the symmetry and phase cues, vanishing point on the horizon (pitch 0: row 59.5), at
// full-resolution column 102, which glance column 20 samples: heading atan(22.5 / 170).
CorridorOptions TwoCues() {
  CorridorOptions options;
  options.gate.enabled = false;
  for (HeadingCueOptions& c : options.heading.cues) c.weight = 0.0;
  options.heading.cues[static_cast<int>(HeadingCue::kSymmetry)].weight = 1.0;
  options.heading.cues[static_cast<int>(HeadingCue::kPhase)].weight = 1.0;
  return options;
}

double Fused(const CorridorOptions& options) {
  Perceiver perceiver(options, Camera160());
  const auto img = RadialFrame(102.0, 59.5);
  const PerceptionResult r = perceiver.Process(GrayView{img.data(), 160, 120, 160}, std::nullopt, 0.1);
  EXPECT_TRUE(r.heading_deg.has_value());
  return r.heading_deg.value_or(1e9);
}

const double kTruthDeg = RadToDeg(std::atan(22.5 / 170.0));
const double kColumnDeg = RadToDeg(std::atan(5.0 / 170.0));  // one glance column at the centre

TEST(HeadingFusion, CurveSumFindsTheCorridorAxis) {
  const CorridorOptions options = TwoCues();
  ASSERT_TRUE(options.heading.fuse_curves);
  EXPECT_NEAR(Fused(options), kTruthDeg, 0.5 * kColumnDeg);
}

TEST(HeadingFusion, CurveSumAppliesEachCuesCalibration) {
  // Both cues calibrated with the same +4 deg bias: their resampled curves peak 4 deg further
  // left-turned, and so does the fused heading.
  CorridorOptions options = TwoCues();
  options.heading.cues[static_cast<int>(HeadingCue::kSymmetry)].bias_deg = 4.0;
  options.heading.cues[static_cast<int>(HeadingCue::kPhase)].bias_deg = 4.0;
  EXPECT_NEAR(Fused(options), kTruthDeg + 4.0, 0.5 * kColumnDeg);
  // A scale of 2 on both doubles the heading of the peak column.
  options = TwoCues();
  options.heading.cues[static_cast<int>(HeadingCue::kSymmetry)].scale = 2.0;
  options.heading.cues[static_cast<int>(HeadingCue::kPhase)].scale = 2.0;
  EXPECT_NEAR(Fused(options), 2.0 * kTruthDeg, kColumnDeg);
}

TEST(HeadingFusion, ConsensusOfEstimatesStaysAvailable) {
  CorridorOptions options = TwoCues();
  options.heading.fuse_curves = false;
  EXPECT_NEAR(Fused(options), kTruthDeg, kColumnDeg);
}

TEST(HeadingFusion, NoUsableCurveGivesNoHeading) {
  // A uniform frame: no cue can score it, so the curve sum has nothing to add.
  Perceiver perceiver(TwoCues(), Camera160());
  std::vector<std::uint8_t> img(160 * 120, 90);
  const PerceptionResult r = perceiver.Process(GrayView{img.data(), 160, 120, 160}, std::nullopt, 0.1);
  EXPECT_FALSE(r.heading_deg.has_value());
  for (const HeadingMeasureResult& h : r.heading) EXPECT_FALSE(h.fused);
}

GrayView View(const std::vector<std::uint8_t>& img) { return GrayView{img.data(), 160, 120, 160}; }

constexpr int kSym = static_cast<int>(HeadingCue::kSymmetry);
constexpr int kPhase = static_cast<int>(HeadingCue::kPhase);

TEST(HeadingFilter, OffByDefaultTheHeadingIsThePerFrameFusion) {
  ASSERT_FALSE(CorridorOptions{}.heading.filter.enabled);
  Perceiver perceiver(TwoCues(), Camera160());
  const auto img = RadialFrame(102.0, 59.5);
  for (int i = 0; i < 3; ++i) {
    const PerceptionResult r = perceiver.Process(View(img), std::nullopt, 0.1, 5.0);  // a turn changes nothing
    ASSERT_TRUE(r.heading_deg && r.heading_instant_deg);
    EXPECT_EQ(*r.heading_deg, *r.heading_instant_deg);
  }
}

TEST(HeadingFilter, WeighsTheCuesByTheirSigmaOverFrames) {
  // No process noise and no outlier gate: the filter is recursive least squares, so after n
  // identical frames its state is the 1/σ²-weighted mean of the two cues' estimates.
  CorridorOptions options = TwoCues();
  options.heading.cues[kSym].bias_deg = 3.0;  // the two cues now disagree by about 4 deg
  options.heading.cues[kPhase].bias_deg = -1.0;
  options.heading.cues[kSym].std_deg = 4.0;
  options.heading.cues[kPhase].std_deg = 2.0;
  options.heading.filter.enabled = true;
  options.heading.filter.process_std_deg = 0.0;
  options.heading.filter.odom_noise_fraction = 0.0;
  options.heading.filter.gate_chi2 = 1e9;
  Perceiver perceiver(options, Camera160());
  const auto img = RadialFrame(102.0, 59.5);
  for (int i = 0; i < 4; ++i) {
    const PerceptionResult r = perceiver.Process(View(img), std::nullopt, 0.1, 0.0);
    ASSERT_TRUE(r.heading[kSym].heading_deg && r.heading[kPhase].heading_deg && r.heading_deg);
    const double zs = *r.heading[kSym].heading_deg, zp = *r.heading[kPhase].heading_deg;
    ASSERT_GT(zs - zp, 2.0);
    EXPECT_NEAR(*r.heading_deg, (zs / 16.0 + zp / 4.0) / (1.0 / 16.0 + 1.0 / 4.0), 1e-9) << i;
    EXPECT_NE(*r.heading_deg, *r.heading_instant_deg);
  }
}

CorridorOptions PhaseOnlyFiltered() {
  CorridorOptions options = TwoCues();
  options.heading.cues[kSym].weight = 0.0;
  options.heading.cues[kPhase].std_deg = 8.0;
  options.heading.filter.enabled = true;
  return options;
}

TEST(HeadingFilter, SkippedFramesCarryTheOdometryTurnToTheNextProcessedFrame) {
  CorridorOptions options = PhaseOnlyFiltered();
  options.gate.enabled = true;  // identical frames: skipped until the forced one
  options.gate.threshold = 0.5;
  options.gate.max_skipped_frames = 5;
  Perceiver perceiver(options, Camera160());
  const auto img = RadialFrame(102.0, 59.5);
  const PerceptionResult first = perceiver.Process(View(img), std::nullopt, 0.1);
  ASSERT_TRUE(first.processed && first.heading_deg);
  const double z = *first.heading_deg;  // the first measurement initialises the state
  EXPECT_EQ(z, *first.heading[kPhase].heading_deg);
  for (int i = 0; i < 5; ++i) {
    const PerceptionResult r = perceiver.Process(View(img), 0.0, 0.1, 2.0);  // turning left 2 deg a frame
    EXPECT_FALSE(r.processed);
    EXPECT_FALSE(r.heading_deg);
  }
  const PerceptionResult r = perceiver.Process(View(img), 0.0, 0.1, 0.0);
  ASSERT_TRUE(r.processed && r.heading_deg);
  ASSERT_NEAR(*r.heading_instant_deg, z, 1e-12);  // the same frame reads the same
  // Predicted z + 10 with variance 64 + 5·(0.1·√0.1 + 0.05·2)² + (0.1·√0.1)² (process noise per
  // √s over 0.1 s frames plus 5 % of each turn), then the update by z (σ 8).
  const double s0 = 0.1 * std::sqrt(0.1);
  const double p = 64.0 + 5.0 * (s0 + 0.1) * (s0 + 0.1) + s0 * s0;
  const double k = p / (p + 64.0);
  EXPECT_NEAR(*r.heading_deg, z + 10.0 * (1.0 - k), 1e-9);
}

TEST(HeadingFilter, ProcessNoiseIsPerSecondAndPerFrameOnlyWithoutAFrameInterval) {
  // One cue, the same frame twice; the second update's gain shows the predicted variance.
  auto second = [](double dt_s) {
    CorridorOptions options = PhaseOnlyFiltered();
    options.heading.filter.process_std_deg_per_sqrt_s = 2.0;
    options.heading.filter.process_std_deg = 5.0;
    Perceiver perceiver(options, Camera160());
    const auto img = RadialFrame(102.0, 59.5);
    const double z = perceiver.Process(View(img), std::nullopt, dt_s, 0.0).heading_deg.value();
    // Turned 4 deg: the prediction is z + 4, pulled back towards z by the gain.
    const double h = perceiver.Process(View(img), std::nullopt, dt_s, 4.0).heading_deg.value();
    return (h - z) / 4.0;  // 1 - gain
  };
  auto expected = [](double step_std) {
    const double sd = step_std + 0.05 * 4.0;
    const double p = 64.0 + sd * sd;
    return 1.0 - p / (p + 64.0);
  };
  EXPECT_NEAR(second(0.25), expected(2.0 * 0.5), 1e-9);  // 2 deg/√s over 0.25 s
  EXPECT_NEAR(second(4.0), expected(2.0 * 2.0), 1e-9);   // ... over 4 s
  EXPECT_NEAR(second(0.0), expected(5.0), 1e-9);         // interval unknown: per frame
}

TEST(HeadingFilter, RejectsAnOutlierAndRestartsAfterRepeatedRejections) {
  CorridorOptions options = PhaseOnlyFiltered();
  options.heading.cues[kPhase].std_deg = 2.0;
  options.heading.filter.reinit_after_rejections = 3;
  Perceiver perceiver(options, Camera160());
  const auto a = RadialFrame(102.0, 59.5);  // right of centre: a positive heading
  const auto b = RadialFrame(50.0, 59.5);   // left of centre: a negative one
  double state = 0.0;
  for (int i = 0; i < 10; ++i) state = perceiver.Process(View(a), std::nullopt, 0.1, 0.0).heading_deg.value();
  const double za = perceiver.Process(View(a), std::nullopt, 0.1, 0.0).heading_instant_deg.value();
  EXPECT_NEAR(state, za, 1e-6);
  ASSERT_GT(za, 5.0);
  for (int i = 0; i < 3; ++i) {  // far outside 3σ of the prediction: rejected, the state holds
    const PerceptionResult r = perceiver.Process(View(b), std::nullopt, 0.1, 0.0);
    ASSERT_LT(*r.heading_instant_deg, -5.0);
    EXPECT_NEAR(*r.heading_deg, za, 1e-6) << i;
  }
  // The fourth one in a row restarts the state from it (a new corridor).
  const PerceptionResult r = perceiver.Process(View(b), std::nullopt, 0.1, 0.0);
  EXPECT_EQ(*r.heading_deg, *r.heading_instant_deg);
  // Reset() forgets the state: the next frame starts it afresh.
  perceiver.Reset();
  const PerceptionResult after = perceiver.Process(View(a), std::nullopt, 0.1, 0.0);
  EXPECT_EQ(*after.heading_deg, *after.heading_instant_deg);
}

TEST(HeadingFilter, AStateTurnedOutOfRangeGivesNoHeading) {
  CorridorOptions options = PhaseOnlyFiltered();
  options.heading.cues[kPhase].std_deg = 0.5;
  Perceiver perceiver(options, Camera160());
  const auto a = RadialFrame(102.0, 59.5);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(perceiver.Process(View(a), std::nullopt, 0.1, 0.0).heading_deg);
  // Turned 60 deg left: the prediction (about 67 deg) lies beyond max_abs_heading_deg (40) and
  // the frame's own estimate is rejected as an outlier.
  const PerceptionResult r = perceiver.Process(View(a), std::nullopt, 0.1, 60.0);
  EXPECT_TRUE(r.heading_instant_deg);
  EXPECT_FALSE(r.heading_deg);
}

TEST(HeadingFilter, InvalidFilterOptionsAreRefused) {
  CorridorOptions options = PhaseOnlyFiltered();
  options.heading.cues[kPhase].std_deg = 0.0;
  EXPECT_NE(options.Validate().find("heading.cues.phase.std_deg must be > 0"), std::string::npos);
  EXPECT_THROW(Perceiver(options, Camera160()), Error);
  options = PhaseOnlyFiltered();
  options.heading.filter.gate_chi2 = -1.0;
  EXPECT_NE(options.Validate().find("heading.filter.gate_chi2 must be > 0"), std::string::npos);
  options = PhaseOnlyFiltered();
  options.heading.filter.reinit_after_rejections = 0;
  EXPECT_NE(options.Validate().find("heading.filter.reinit_after_rejections"), std::string::npos);
}

}  // namespace
}  // namespace squint::corridor
