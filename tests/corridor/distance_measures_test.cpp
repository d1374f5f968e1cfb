// Distance cues: time to contact of a glance scaled about a known point by a known factor (eq. 3),
// and every degenerate input (identical frames, zero gradient, zero denominator, no travel).
#include "squint/corridor/distance_measures.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {
namespace {

// A smooth pattern (low frequencies, so the 32×24 sampling resolves its derivatives), seen
// magnified by `scale` about (cx, cy): I(x) = P((x − c) / scale).
Glance SmoothPattern(double scale, double cx, double cy) {
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v) {
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double x = (u - cx) / scale, y = (v - cy) / scale;
      const double value = 128.0 + 50.0 * std::sin(0.31 * x + 0.17 * y) + 40.0 * std::cos(0.23 * y - 0.27 * x + 0.5) +
                           20.0 * std::sin(0.11 * x * 0.9 + 0.4);
      g.At(u, v) = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  }
  return g;
}

PreparedGlance Prepare(const Glance& g) {
  PreparedGlance p;
  ComputeHistogramAndEntropy(g, 6, p);
  PrepareMeasures(3, 3, p);
  return p;
}

// Approaching a plane at Z by ΔZ per frame magnifies the image by k = Z / (Z − ΔZ); the time to
// contact from the first frame is Z / ΔZ = k / (k − 1) frames. Eq. 3 with derivatives averaged
// over both frames estimates it at the midpoint between them: k / (k − 1) − 1/2.
TEST(TimeToContact, ScaledGlanceGivesKnownTimeWithin5Percent) {
  const double cx = 15.5, cy = 11.5;
  for (double k : {1.02, 1.04, 1.08}) {
    const Glance a = SmoothPattern(1.0, cx, cy);
    const Glance b = SmoothPattern(k, cx, cy);
    const double expected = k / (k - 1.0) - 0.5;
    const auto tau = TimeToContactFrames(a, b, cx, cy);
    ASSERT_TRUE(tau.has_value());
    EXPECT_NEAR(*tau, expected, 0.05 * expected) << "k = " << k;
    // The distance cue: τ × travelled per frame.
    DistanceOptions options;
    TimeToContactDistance ttc(options, cx, cy);
    DistanceMeasureResult r;
    ttc.Measure(Prepare(a), Prepare(b), 0.1, r);
    ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
    EXPECT_NEAR(*r.dist_m, 0.1 * expected, 0.05 * 0.1 * expected);
    EXPECT_NEAR(*r.raw, *tau, 1e-3 * *tau);
  }
}

TEST(TimeToContact, ContractingImageIsNotApproaching) {
  const Glance a = SmoothPattern(1.05, 15.5, 11.5);
  const Glance b = SmoothPattern(1.0, 15.5, 11.5);
  TimeToContactDistance ttc(DistanceOptions{}, 15.5, 11.5);
  DistanceMeasureResult r;
  ttc.Measure(Prepare(a), Prepare(b), 0.1, r);
  EXPECT_FALSE(r.dist_m.has_value());
  EXPECT_EQ(r.reason, Reason::kNotApproaching);
}

TEST(TimeToContact, DegenerateInputs) {
  TimeToContactDistance ttc(DistanceOptions{}, 15.5, 11.5);
  DistanceMeasureResult r;
  const Glance a = SmoothPattern(1.0, 15.5, 11.5);
  // Identical frames.
  ttc.Measure(Prepare(a), Prepare(a), 0.1, r);
  EXPECT_EQ(r.reason, Reason::kIdenticalFrames);
  EXPECT_FALSE(r.dist_m.has_value());
  // Two different uniform frames: no gradient anywhere.
  Glance u1, u2;
  u1.pixels.fill(50);
  u2.pixels.fill(60);
  ttc.Measure(Prepare(u1), Prepare(u2), 0.1, r);
  EXPECT_FALSE(r.dist_m.has_value());
  EXPECT_EQ(r.reason, Reason::kUniformFrame);
  // A gradient but no temporal change where G ≠ 0: a vertical ramp (I_y only) whose one changed
  // pixel sits on the principal point's row and column, so G there is 0 and Σ G·I_t = 0.
  Glance r1;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) r1.At(u, v) = static_cast<std::uint8_t>(40 + 5 * v);
  Glance r2 = r1;
  r2.At(15, 11) = static_cast<std::uint8_t>(r2.At(15, 11) + 1);
  TimeToContactDistance centred(DistanceOptions{}, 15.0, 11.0);
  // G at (15, 11) is x·I_x + y·I_y with x = y = 0, so that pixel adds nothing: the denominator is 0.
  EXPECT_FALSE(TimeToContactFrames(r1, r2, 15.0, 11.0).has_value());
  centred.Measure(Prepare(r1), Prepare(r2), 0.1, r);
  EXPECT_EQ(r.reason, Reason::kTtcDenominatorZero);
  // No travelled distance.
  const Glance b = SmoothPattern(1.04, 15.5, 11.5);
  ttc.Measure(Prepare(a), Prepare(b), std::nullopt, r);
  EXPECT_EQ(r.reason, Reason::kNoTravel);
  EXPECT_TRUE(r.raw.has_value());
}

TEST(JeffreyDistance, FollowsTheLinearModelAndRejectsIdenticalFrames) {
  DistanceOptions options;
  options.alpha2 = 10.0;
  options.beta2 = 30.0;
  JeffreyDistance jeffrey(options);
  const PreparedGlance a = Prepare(SmoothPattern(1.0, 15.5, 11.5));
  const PreparedGlance b = Prepare(SmoothPattern(1.08, 15.5, 11.5));
  DistanceMeasureResult r;
  jeffrey.Measure(a, b, std::nullopt, r);
  ASSERT_TRUE(r.raw.has_value());
  ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
  EXPECT_GT(*r.raw, 0.0);
  EXPECT_NEAR(*r.dist_m, 30.0 - 10.0 * *r.raw, 1e-9);
  jeffrey.Measure(a, a, std::nullopt, r);
  EXPECT_EQ(r.reason, Reason::kIdenticalFrames);
}

TEST(EntropyDistance, InverseOfTheEntropyChange) {
  DistanceOptions options;
  options.alpha3 = 0.5;
  EntropyDistance entropy(options);
  const PreparedGlance a = Prepare(SmoothPattern(1.0, 15.5, 11.5));
  PreparedGlance b = a;
  // Same pixels' histogram changed: shift a block of pixels to a new level.
  Glance g = a.glance;
  for (int i = 0; i < 200; ++i) g.pixels[i] = 255;
  b = Prepare(g);
  DistanceMeasureResult r;
  entropy.Measure(a, b, std::nullopt, r);
  ASSERT_TRUE(r.raw.has_value());
  ASSERT_NE(*r.raw, 0.0);
  ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
  EXPECT_NEAR(*r.dist_m, 0.5 / std::abs(a.entropy - b.entropy), 1e-9);
  entropy.Measure(a, a, std::nullopt, r);
  EXPECT_EQ(r.reason, Reason::kIdenticalFrames);
}

}  // namespace
}  // namespace squint::corridor
