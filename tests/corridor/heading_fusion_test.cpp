// Heading fusion in the Perceiver: the sum of the cues' normalised curves (default) follows each
// cue's calibration (scale, bias) when it resamples the curve onto the fused heading grid, and
// the paper-style consensus of the cues' own estimates stays available.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "squint/core/angles.hpp"
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

}  // namespace
}  // namespace squint::corridor
