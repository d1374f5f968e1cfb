// Distance cues: time to contact of a glance scaled about a known point by a known factor (eq. 3),
// and every degenerate input (identical frames, zero gradient, zero denominator, no travel).
#include "squint/corridor/distance_measures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>

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
    // The distance cue: τ × travelled per frame, from the middle of the baseline to the
    // current frame (− s/2). Scaling by k = Z1/Z2 with Z1 − Z2 = 0.1 m puts the current frame
    // 0.1 · (k/(k−1) − 1) m from the plane.
    DistanceOptions options;
    TimeToContactDistance ttc(options, cx, cy);
    DistanceMeasureResult r;
    ttc.Measure(Prepare(a), Prepare(b), 0.1, r);
    ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
    const double current_m = 0.1 * (k / (k - 1.0) - 1.0);
    EXPECT_NEAR(*r.dist_m, current_m, 0.05 * current_m);
    EXPECT_EQ(r.baseline_frames, 1);
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

TEST(TimeToContact, LongerBaselineGivesTheCurrentDistance) {
  // Frames 4 apart, 0.1 m per frame: the plane is 10 m from the current frame and 10.4 m from
  // the earlier one, a magnification of k = 10.4 / 10.
  const double cx = 15.5, cy = 11.5;
  const Glance earlier = SmoothPattern(1.0, cx, cy);
  const Glance current = SmoothPattern(10.4 / 10.0, cx, cy);
  TimeToContactDistance ttc(DistanceOptions{}, cx, cy);
  DistanceMeasureResult r;
  ttc.MeasureBaseline(earlier, current, 4, 0.4, r);
  ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
  EXPECT_EQ(r.baseline_frames, 4);
  EXPECT_NEAR(*r.dist_m, 10.0, 0.5);
  ASSERT_TRUE(r.model_input.has_value());
  EXPECT_DOUBLE_EQ(*r.model_input, *r.raw * 0.4 - 0.2);
  EXPECT_EQ(r.instant_m, r.dist_m);
}

TEST(TimeToContact, GainCompensationIgnoresABrightnessChange) {
  // The same 4 % magnification, the second frame 10 % brighter plus 5 grey levels (camera gain).
  const double cx = 15.5, cy = 11.5, k = 1.04;
  const Glance a = SmoothPattern(1.0, cx, cy);
  Glance b = SmoothPattern(k, cx, cy);
  for (auto& p : b.pixels) p = static_cast<std::uint8_t>(std::lround(std::min(255.0, 1.1 * p + 5.0)));
  const double expected = k / (k - 1.0) - 0.5;
  const auto with = TimeToContactFrames(a, b, cx, cy, true);
  ASSERT_TRUE(with.has_value());
  EXPECT_NEAR(*with, expected, 0.05 * expected);
  // Without compensation the brightness change passes for expansion or contraction.
  const auto without = TimeToContactFrames(a, b, cx, cy, false);
  // (here 22.5 frames against 25.5, the compensated 25.2).
  ASSERT_TRUE(without.has_value());
  EXPECT_GT(std::abs(*without - expected), 0.1 * expected);
  EXPECT_GT(std::abs(*without - expected), 5.0 * std::abs(*with - expected));
  // With no brightness change both agree within 5 %.
  const Glance c = SmoothPattern(k, cx, cy);
  EXPECT_NEAR(*TimeToContactFrames(a, c, cx, cy, true), *TimeToContactFrames(a, c, cx, cy, false), 0.05 * expected);
}

// A brick-like texture of periods 5–9 pixels (the drives' end walls), seen magnified by `scale`
// about (cx, cy): a small window about the centre still holds several periods.
Glance TexturedPattern(double scale, double cx, double cy) {
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double x = (u - cx) / scale, y = (v - cy) / scale;
      const double value = 128.0 + 45.0 * std::sin(0.9 * x + 0.3 * y) + 35.0 * std::cos(0.7 * y - 0.4 * x + 0.5) +
                           25.0 * std::sin(1.1 * y + 0.2);
      g.At(u, v) = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  return g;
}

// The scale search (the default time to contact): the magnification of a glance scaled about a
// known point, whatever the gain and offset of the second frame.
TEST(ExpansionScale, RecoversAKnownMagnificationDespiteAGainChange) {
  const double cx = 15.5, cy = 10.0;
  for (double k : {1.02, 1.05, 1.12, 1.3}) {
    const Glance a = SmoothPattern(1.0, cx, cy);
    Glance b = SmoothPattern(k, cx, cy);
    const auto m = ExpansionScale(a, b, cx, cy, 32, 24, 1.5);
    ASSERT_TRUE(m.has_value()) << "k = " << k;
    EXPECT_NEAR(m->scale, k, 0.004) << "k = " << k;
    EXPECT_GT(m->ncc, 0.99);
    // 15 % brighter minus 8 grey levels (the webcam gain jumps of ../shared/data/drive-*).
    for (auto& p : b.pixels) p = static_cast<std::uint8_t>(std::lround(std::clamp(1.15 * p - 8.0, 0.0, 255.0)));
    const auto g = ExpansionScale(a, b, cx, cy, 32, 24, 1.5);
    ASSERT_TRUE(g.has_value());
    EXPECT_NEAR(g->scale, k, 0.004) << "k = " << k << " with a gain change";
  }
}

// Gauss–Newton from a prediction (the fast path): starting up to ±0.04 off, it reaches the
// known magnification without the grid, gain change included; a prediction into the wrong
// basin of a periodic texture (poor NCC) falls back to the grid and still finds it.
TEST(ExpansionScale, RefinesFromAPredictionToTheKnownMagnification) {
  const double cx = 15.5, cy = 10.0;
  for (double k : {1.02, 1.05, 1.12, 1.3}) {
    const Glance a = SmoothPattern(1.0, cx, cy);
    Glance b = SmoothPattern(k, cx, cy);
    for (auto& p : b.pixels) p = static_cast<std::uint8_t>(std::lround(std::clamp(1.15 * p - 8.0, 0.0, 255.0)));
    const auto grid = ExpansionScale(a, b, cx, cy, 32, 24, 1.5);
    ASSERT_TRUE(grid.has_value());
    EXPECT_TRUE(grid->searched);
    for (double off : {-0.04, -0.01, 0.0, 0.02, 0.04}) {
      const auto m = ExpansionScale(a, b, cx, cy, 32, 24, 1.5, k + off, 0.95);
      ASSERT_TRUE(m.has_value()) << "k = " << k << " off " << off;
      EXPECT_FALSE(m->searched) << "k = " << k << " off " << off;
      EXPECT_NEAR(m->scale, k, 0.004) << "k = " << k << " off " << off;
      EXPECT_NEAR(m->scale, grid->scale, 0.002) << "k = " << k << " off " << off;
      EXPECT_GT(m->ncc, 0.99);
    }
  }
  // A contracting image from a prediction above 1: exactly 1, as the grid says.
  const auto away = ExpansionScale(SmoothPattern(1.1, cx, cy), SmoothPattern(1.0, cx, cy), cx, cy, 32, 24, 1.5,
                                   1.05, 0.5);
  ASSERT_TRUE(away.has_value());
  EXPECT_DOUBLE_EQ(away->scale, 1.0);
  // Unreachable acceptance (NCC ≥ 1.01): the grid runs and its answer stands.
  const Glance ta = TexturedPattern(1.0, cx, cy), tb = TexturedPattern(1.08, cx, cy);
  const auto fallback = ExpansionScale(ta, tb, cx, cy, 32, 24, 1.5, 1.4, 1.01);
  ASSERT_TRUE(fallback.has_value());
  EXPECT_TRUE(fallback->searched);
  EXPECT_NEAR(fallback->scale, 1.08, 0.01);
}

TEST(ExpansionScale, WindowContractionAndDegenerateInputs) {
  const double cx = 15.5, cy = 11.5;
  const Glance a = SmoothPattern(1.0, cx, cy);
  // A 13 × 9 window about the centre (the end wall at ~10 m) still finds the scale.
  const auto small =
      ExpansionScale(TexturedPattern(1.0, cx, cy), TexturedPattern(1.08, cx, cy), cx, cy, 6, 4, 1.5);
  ASSERT_TRUE(small.has_value());
  EXPECT_NEAR(small->scale, 1.08, 0.01);
  // A contracting image (driving away) has its best match at 1: no expansion.
  const auto away = ExpansionScale(SmoothPattern(1.1, cx, cy), a, cx, cy, 32, 24, 1.5);
  ASSERT_TRUE(away.has_value());
  EXPECT_DOUBLE_EQ(away->scale, 1.0);
  // A uniform frame, a window under 12 pixels, a non-finite centre: none.
  Glance flat;
  flat.pixels.fill(90);
  EXPECT_FALSE(ExpansionScale(a, flat, cx, cy, 32, 24, 1.5).has_value());
  EXPECT_FALSE(ExpansionScale(a, a, cx, cy, 1, 1, 1.5).has_value());
  EXPECT_FALSE(ExpansionScale(a, a, std::nan(""), cy, 32, 24, 1.5).has_value());
  EXPECT_FALSE(ExpansionScale(a, a, cx, cy, 32, 24, 1.0).has_value());
}

// Far-structure cells: the end wall (the middle columns) magnified by 1.04, the near walls on
// either side by 1.2. The window's single magnification lies between; a low quantile of the
// cells' magnifications recovers the end wall's.
TEST(CellExpansionScales, LowQuantileRecoversTheFarthestStructure) {
  const double cx = 15.5, cy = 11.5;
  const Glance a = TexturedPattern(1.0, cx, cy);
  Glance b;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double k = std::abs(u - cx) <= 5.0 ? 1.04 : 1.2;
      b.At(u, v) = TexturedPattern(k, cx, cy).At(u, v);
    }
  const auto whole = ExpansionScale(a, b, cx, cy, 15, 11, 1.5);
  ASSERT_TRUE(whole.has_value());
  auto cells = CellExpansionScales(a, b, cx, cy, 15, 11, 1.5, whole->scale, 5.0, 2.0, 0.8);
  ASSERT_TRUE(cells.has_value());
  ASSERT_GE(cells->count, 6);
  const double far = LowerQuantile(std::span<double>(cells->scale.data(), cells->count), 0.25);
  EXPECT_NEAR(far, 1.04, 0.01);
  EXPECT_GT(whole->scale, 1.06);  // the single window is pulled towards the near walls
  // The upper quantile is the near walls'.
  const double near = LowerQuantile(std::span<double>(cells->scale.data(), cells->count), 1.0);
  EXPECT_NEAR(near, 1.2, 0.02);
  // Degenerate inputs: no cells for a bad centre, no valid cells on a uniform frame.
  EXPECT_FALSE(CellExpansionScales(a, b, std::nan(""), cy, 15, 11, 1.5, 1.0, 5.0, 2.0, 0.8).has_value());
  Glance flat;
  flat.pixels.fill(90);
  const auto none = CellExpansionScales(a, flat, cx, cy, 15, 11, 1.5, 1.0, 5.0, 2.0, 0.8);
  ASSERT_TRUE(none.has_value());
  EXPECT_EQ(none->count, 0);
  std::array<double, 5> v = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(LowerQuantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(LowerQuantile(v, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(LowerQuantile(v, 1.0), 5.0);
}

// The end of the corridor (a 15 × 13 px block about the expansion centre) magnified by 1.04,
// everything around it by 1.2: with the two cells nearest the centre the scale search reads the
// end wall's distance, s / 0.04 = 10 m for 0.4 m of travel; with every cell's median, the near
// structure's, about 2 m.
TEST(TimeToContact, NearestCellsReadTheEndOfTheCorridor) {
  const double cx = 15.5, cy = 11.5;
  const Glance a = TexturedPattern(1.0, cx, cy);
  Glance b;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double k = std::abs(u - cx) <= 7.0 && std::abs(v - cy) <= 6.0 ? 1.04 : 1.2;
      b.At(u, v) = TexturedPattern(k, cx, cy).At(u, v);
    }
  DistanceOptions o;
  o.ttc_cell_px = 6.0;
  o.ttc_cell_quantile = 0.5;
  o.ttc_cell_nearest = 2;
  o.ttc_cell_min_count = 2;  // counted among the nearest cells
  DistanceMeasureResult near_cells;
  TimeToContactDistance(o, cx, cy).MeasureScale(a, b, 4, 0.4, std::nullopt, near_cells);
  ASSERT_TRUE(near_cells.model_input.has_value());
  EXPECT_NEAR(*near_cells.model_input, 10.0, 1.0);
  o.ttc_cell_nearest = 0;
  DistanceMeasureResult all_cells;
  TimeToContactDistance(o, cx, cy).MeasureScale(a, b, 4, 0.4, std::nullopt, all_cells);
  ASSERT_TRUE(all_cells.model_input.has_value());
  EXPECT_LT(*all_cells.model_input, 3.0);
}

TEST(TimeToContact, ScaleSearchGivesTheCurrentDistanceAndRefusesPlainWalls) {
  // 4 frames of 0.1 m: the plane is 10 m from the current frame, 10.4 m from the earlier one.
  const double cx = 15.5, cy = 11.5;
  const Glance earlier = TexturedPattern(1.0, cx, cy);
  const Glance current = TexturedPattern(10.4 / 10.0, cx, cy);
  DistanceOptions options;
  // Glance focal length 40 px, camera 1 m high: at a reference of 10 m the window is ±6 × ±4.
  const TimeToContactDistance ttc(options, cx, cy, 40.0, 1.0);
  DistanceMeasureResult r;
  ttc.MeasureScale(earlier, current, 4, 0.4, 10.0, r);
  ASSERT_TRUE(r.dist_m.has_value()) << ReasonText(r.reason);
  EXPECT_NEAR(*r.dist_m, 10.0, 0.5);
  EXPECT_EQ(r.baseline_frames, 4);
  ASSERT_TRUE(r.raw.has_value());
  EXPECT_NEAR(*r.raw, 0.04, 0.002);  // σ − 1
  EXPECT_DOUBLE_EQ(*r.model_input, 0.4 / *r.raw);
  // No reference yet: the whole glance, the same answer.
  ttc.MeasureScale(earlier, current, 4, 0.4, std::nullopt, r);
  ASSERT_TRUE(r.dist_m.has_value());
  EXPECT_NEAR(*r.dist_m, 10.0, 0.5);
  // A plain wall close up (contrast below ttc_min_contrast): no estimate, not "very far".
  Glance plain;
  for (int i = 0; i < kGlancePixels; ++i) plain.pixels[i] = static_cast<std::uint8_t>(200 + (i % 2));
  ttc.MeasureScale(plain, plain, 1, 0.1, 1.0, r);
  EXPECT_EQ(r.reason, Reason::kIdenticalFrames);
  Glance plain2 = plain;
  plain2.pixels[100] = 203;
  ttc.MeasureScale(plain, plain2, 1, 0.1, 1.0, r);
  EXPECT_FALSE(r.dist_m.has_value());
  EXPECT_EQ(r.reason, Reason::kZeroGradient);
  EXPECT_FALSE(r.raw.has_value());
  // Driving away: no expansion.
  ttc.MeasureScale(current, earlier, 4, 0.4, 10.0, r);
  EXPECT_EQ(r.reason, Reason::kNotApproaching);
  // No travel known.
  ttc.MeasureScale(earlier, current, 4, std::nullopt, 10.0, r);
  EXPECT_EQ(r.reason, Reason::kNoTravel);
}

// The binomial smoothing before the scale search: a constant stays, an impulse spreads as
// [1 2 1] ⊗ [1 2 1] / 16 (rounded), a border impulse has its outside neighbours folded back.
TEST(SmoothGlance, KnownAnswers) {
  Glance flat, out;
  flat.pixels.fill(77);
  SmoothGlance(flat, out);
  for (auto p : out.pixels) EXPECT_EQ(p, 77);
  Glance impulse;
  impulse.At(10, 10) = 160;
  SmoothGlance(impulse, out);
  EXPECT_EQ(out.At(10, 10), 40);  // 160 · 4/16
  EXPECT_EQ(out.At(9, 10), 20);   // 160 · 2/16
  EXPECT_EQ(out.At(10, 11), 20);
  EXPECT_EQ(out.At(11, 11), 10);  // 160 · 1/16
  EXPECT_EQ(out.At(12, 10), 0);
  int sum = 0;
  for (auto p : out.pixels) sum += p;
  EXPECT_EQ(sum, 160);
  Glance corner;
  corner.At(0, 0) = 160;
  SmoothGlance(corner, out);
  EXPECT_EQ(out.At(0, 0), 90);  // (2+1)(2+1) / 16 · 160 (the edge pixel repeated)
  EXPECT_EQ(out.At(1, 0), 30);  // 1 · (2+1) / 16 · 160
}

TEST(DistanceMeasures, ValidityWindowPerCue) {
  DistanceOptions options;
  options.alpha2 = 1.0;
  options.beta2 = 10.0;
  options.valid_min_m[1] = 2.0;
  options.valid_max_m[1] = 6.0;
  const JeffreyDistance jeffrey(options);
  EXPECT_FALSE(jeffrey.Distance(9.0).has_value());  // 1 m: below the window
  ASSERT_TRUE(jeffrey.Distance(6.0).has_value());   // 4 m
  EXPECT_DOUBLE_EQ(*jeffrey.Distance(6.0), 4.0);
  EXPECT_FALSE(jeffrey.Distance(3.0).has_value());  // 7 m: above it
  // The other cues keep the default window.
  options.alpha3 = 1.0;
  const EntropyDistance entropy(options);
  ASSERT_TRUE(entropy.Distance(-0.5).has_value());  // |ΔH| is used
  EXPECT_DOUBLE_EQ(*entropy.Distance(-0.5), 2.0);
  EXPECT_FALSE(entropy.Distance(0.0).has_value());
  options.ttc_scale = 2.0;
  options.ttc_bias_m = 1.0;
  const TimeToContactDistance ttc(options, 15.5, 11.5);
  EXPECT_DOUBLE_EQ(*ttc.Distance(3.0), 7.0);
  EXPECT_FALSE(ttc.Distance(-1.0).has_value());  // below min_m = 0
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
