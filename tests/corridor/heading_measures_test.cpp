// Heading cues on constructed glances whose answer is known: a symmetric, scale-invariant
// corridor pattern with its axis at a known column (every cue within one column), a bright blob
// at a known column, and every degenerate input (uniform frame, zero gradient, no bright cluster).
#include "squint/corridor/heading_measures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "squint/corridor/information.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A "corridor" seen from its axis: intensity depends only on the direction from the vanishing
// point (vx, vy), as corridor edges do, so the image is self-similar under scaling about that
// point; cos(k·θ) with even k is mirror-symmetric about the vertical through it.
Glance RadialCorridor(double vx, double vy, int k = 6, double amplitude = 100.0) {
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v) {
    for (int u = 0; u < kGlanceWidth; ++u) {
      const double theta = std::atan2(v - vy, u - vx);
      const double value = 128.0 + amplitude * std::cos(k * theta);
      g.At(u, v) = static_cast<std::uint8_t>(std::lround(value));
    }
  }
  return g;
}

// The corridor each cue looks for, all with their axis at column `axis`: the radial pattern for
// symmetry, phase and vanishing point; plus ceiling lights on the axis for the bright cue; and for
// entropy the variety of depths down the corridor (§4.1.1), modelled as texture whose contrast
// falls off symmetrically away from the axis.
Glance CorridorFor(HeadingCue cue, double axis) {
  if (cue == HeadingCue::kEntropy) {
    Glance g;
    for (int v = 0; v < kGlanceHeight; ++v) {
      const int texture = ((v * 37 + 11) % 17) - 8;  // a fixed pseudo-random level per row
      for (int u = 0; u < kGlanceWidth; ++u) {
        const double contrast = std::max(0.0, 1.0 - std::abs(u - axis) / 8.0);
        g.At(u, v) = static_cast<std::uint8_t>(std::lround(128.0 + 14.0 * contrast * texture));
      }
    }
    return g;
  }
  Glance g = RadialCorridor(axis, 9.5);
  if (cue == HeadingCue::kBright) {
    for (int v = 0; v < kGlanceHeight; ++v)
      for (int u = 0; u < kGlanceWidth; ++u) g.At(u, v) = static_cast<std::uint8_t>(g.At(u, v) * 3 / 4);
    for (int v : {1, 3, 5}) g.At(static_cast<int>(axis), v) = 255;
  }
  return g;
}

PreparedGlance Prepare(const Glance& g, const HeadingOptions& o = {}) {
  PreparedGlance p;
  ComputeHistogramAndEntropy(g, 6, p);
  PrepareMeasures(o.column_bits, o.vanishing_bits, p);
  return p;
}

class EveryHeadingCue : public ::testing::TestWithParam<HeadingCue> {};

// The axis lies on a pixel-centre column; a one-column tolerance is the measures' resolution.
TEST_P(EveryHeadingCue, FindsTheAxisOfASymmetricCorridor) {
  for (double axis : {10.0, 15.0, 19.0}) {
    HeadingOptions options;
    // The glance camera's horizon passes through the corridor's vanishing point (row 9.5).
    const auto measure = MakeHeadingMeasure(GetParam(), options, 9.5);
    HeadingMeasureResult r;
    measure->Measure(Prepare(CorridorFor(GetParam(), axis)), r);
    ASSERT_TRUE(r.column_px.has_value()) << CueName(GetParam()) << " axis " << axis << ": " << ReasonText(r.reason);
    EXPECT_NEAR(*r.column_px, axis, 1.0) << CueName(GetParam());
    EXPECT_EQ(r.reason, Reason::kNone);
    EXPECT_GT(r.confidence, 0.0);
  }
}

TEST_P(EveryHeadingCue, UniformFrameGivesNoEstimate) {
  Glance g;
  g.pixels.fill(97);
  const auto measure = MakeHeadingMeasure(GetParam(), HeadingOptions{});
  HeadingMeasureResult r;
  measure->Measure(Prepare(g), r);
  EXPECT_FALSE(r.column_px.has_value());
  EXPECT_NE(r.reason, Reason::kNone);
  for (float c : r.curve) EXPECT_TRUE(std::isfinite(c));
}

INSTANTIATE_TEST_SUITE_P(Cues, EveryHeadingCue,
                         ::testing::Values(HeadingCue::kEntropy, HeadingCue::kSymmetry, HeadingCue::kPhase,
                                           HeadingCue::kVanishing, HeadingCue::kBright),
                         [](const auto& param_info) { return std::string(CueName(param_info.param)); });

TEST(BrightHeading, FindsABlobAtAKnownColumn) {
  for (int centre : {4, 12, 23}) {
    Glance g;
    g.pixels.fill(60);
    // A 3-wide bright blob in the upper rows, centred on `centre`.
    for (int v = 2; v < 6; ++v)
      for (int u = centre - 1; u <= centre + 1; ++u) g.At(u, v) = 250;
    // Darker texture elsewhere so the k-means split has two real clusters.
    for (int v = 0; v < kGlanceHeight; ++v)
      for (int u = 0; u < kGlanceWidth; ++u)
        if ((u + v) % 5 == 0 && g.At(u, v) != 250) g.At(u, v) = 90;
    BrightHeading bright(HeadingOptions{});
    HeadingMeasureResult r;
    bright.Measure(Prepare(g), r);
    ASSERT_TRUE(r.column_px.has_value()) << ReasonText(r.reason);
    EXPECT_NEAR(*r.column_px, centre, 0.5);
    EXPECT_EQ(r.curve[centre], 4.0f);  // four bright rows in that column
    EXPECT_EQ(r.curve[centre + 3], 0.0f);
  }
}

TEST(BrightHeading, TwoLevelsTooCloseAreNoBrightCluster) {
  Glance g;
  for (int i = 0; i < kGlancePixels; ++i) g.pixels[i] = static_cast<std::uint8_t>(100 + (i % 3));  // 100..102
  BrightHeading bright(HeadingOptions{});
  HeadingMeasureResult r;
  bright.Measure(Prepare(g), r);
  EXPECT_FALSE(r.column_px.has_value());
  EXPECT_EQ(r.reason, Reason::kNoBrightCluster);
}

TEST(PhaseHeading, HorizontalStripesHaveNoUsableGradient) {
  // Only horizontal edges: every gradient is vertical, whose phase ±90° is ambiguous.
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) g.At(u, v) = (v / 3) % 2 ? 200 : 40;
  PhaseHeading phase(HeadingOptions{});
  HeadingMeasureResult r;
  phase.Measure(Prepare(g), r);
  EXPECT_FALSE(r.column_px.has_value());
  EXPECT_EQ(r.reason, Reason::kZeroGradient);
}

TEST(PhaseHeading, WeakGradientBelowThresholdIsZeroGradient) {
  // A ramp of one grey level per 4 columns: Sobel magnitude far below phase_min_gradient.
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) g.At(u, v) = static_cast<std::uint8_t>(100 + u / 4);
  PhaseHeading phase(HeadingOptions{});
  HeadingMeasureResult r;
  phase.Measure(Prepare(g), r);
  EXPECT_EQ(r.reason, Reason::kZeroGradient);
}

TEST(PhaseHeading, LineVoteFindsTheVanishingPointOnTheHorizon) {
  // Edges radiating from (vx, 9.5) cross the horizon row 9.5 at vx, wherever they are; the
  // border columns 0 and 31 are excluded (an argmax there may lie outside the view).
  for (double vx : {3.0, 7.25, 15.0, 22.25, 28.0}) {
    PhaseHeading phase(HeadingOptions{}, 9.5);
    HeadingMeasureResult r;
    phase.Measure(Prepare(RadialCorridor(vx, 9.5)), r);
    ASSERT_TRUE(r.column_px.has_value()) << vx << ": " << ReasonText(r.reason);
    EXPECT_NEAR(*r.column_px, vx, 0.5) << vx;
    EXPECT_GT(r.confidence, 0.5) << vx;
    const int peak = static_cast<int>(std::lround(vx));
    EXPECT_EQ(std::max_element(r.curve.begin(), r.curve.end()) - r.curve.begin(), peak) << vx;
  }
}

TEST(PhaseHeading, LineVoteIgnoresVerticalEdges) {
  // Door frames and wall corners (vertical edges) do not run down the corridor: no votes.
  Glance g;
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u < kGlanceWidth; ++u) g.At(u, v) = (u / 4) % 2 ? 210 : 30;
  PhaseHeading phase(HeadingOptions{}, 11.5);
  HeadingMeasureResult r;
  phase.Measure(Prepare(g), r);
  EXPECT_FALSE(r.column_px.has_value());
  EXPECT_EQ(r.reason, Reason::kZeroGradient);
}

TEST(PhaseHeading, LineVoteWithoutACameraUsesTheMiddleRow) {
  // No horizon given: the lines are extended to the glance's middle row, 11.5.
  PhaseHeading phase(HeadingOptions{});
  HeadingMeasureResult r;
  phase.Measure(Prepare(RadialCorridor(12.0, 11.5)), r);
  ASSERT_TRUE(r.column_px.has_value()) << ReasonText(r.reason);
  EXPECT_NEAR(*r.column_px, 12.0, 0.5);
}

TEST(PhaseHeading, PaperBalanceFormFindsTheAxis) {
  HeadingOptions options;
  options.phase_line_vote = false;
  for (double axis : {10.0, 15.0, 19.0}) {
    PhaseHeading phase(options);
    HeadingMeasureResult r;
    phase.Measure(Prepare(RadialCorridor(axis, 9.5)), r);
    ASSERT_TRUE(r.column_px.has_value()) << axis << ": " << ReasonText(r.reason);
    EXPECT_NEAR(*r.column_px, axis, 1.0);
  }
}

// A near wall seen at the left border: six horizontal bands (ceiling, wall, skirting, floor...:
// intensity depends on the row only) in columns 0..6, which mirror onto themselves about
// column 3; the rest is the corridor's radial pattern (lower contrast) about column 20. Per pair
// the narrow banded window is the more symmetric (its MI is the whole band entropy), but it
// holds 3 pairs per row against 8.
Glance BandedBorderAndCorridor() {
  Glance g = RadialCorridor(20.0, 11.5, 6, 60.0);
  for (int v = 0; v < kGlanceHeight; ++v)
    for (int u = 0; u <= 6; ++u) g.At(u, v) = static_cast<std::uint8_t>(16 + 32 * (v / 4));
  return g;
}

TEST(SymmetryHeading, PerPairMutualInformationPrefersABandedBorder) {
  HeadingOptions options;
  options.symmetry_significance = false;
  HeadingMeasureResult r;
  SymmetryHeading(options).Measure(Prepare(BandedBorderAndCorridor()), r);
  EXPECT_GT(r.curve[3], r.curve[20]);
  EXPECT_FALSE(r.column_px.has_value());  // the maximum sits on the first scored column
  EXPECT_EQ(r.reason, Reason::kPeakAtBorder);
}

TEST(SymmetryHeading, SignificanceFindsTheCorridorAxisBesideABandedBorder) {
  HeadingMeasureResult r;
  SymmetryHeading(HeadingOptions{}).Measure(Prepare(BandedBorderAndCorridor()), r);
  ASSERT_TRUE(r.column_px.has_value()) << ReasonText(r.reason);
  EXPECT_NEAR(*r.column_px, 20.0, 1.0);
  EXPECT_LT(r.curve[3], r.curve[20]);
}

TEST(EntropyHeading, PeakInTheBorderColumnIsRejected) {
  // Only the leftmost column varies: the entropy maximum sits on the glance edge.
  Glance g;
  g.pixels.fill(50);
  for (int v = 0; v < kGlanceHeight; ++v) g.At(0, v) = static_cast<std::uint8_t>(v * 10);
  EntropyHeading entropy(HeadingOptions{});
  HeadingMeasureResult r;
  entropy.Measure(Prepare(g), r);
  EXPECT_FALSE(r.column_px.has_value());
  EXPECT_EQ(r.reason, Reason::kPeakAtBorder);
}

// The symmetry and vanishing-point kernels (8-/16-bit joint histograms counted for all axes or
// placements at once, n·log n tables) against a direct computation with MutualInformation(), on a
// textured glance, at every bit depth and on the 16-bit-count path (half width > 10).
Glance TexturedGlance() {
  Glance g = RadialCorridor(17.0, 10.5, 6, 70.0);
  std::uint32_t state = 12345u;
  for (std::uint8_t& px : g.pixels) {
    state = state * 1664525u + 1013904223u;
    px = static_cast<std::uint8_t>(std::clamp(static_cast<int>(px) + static_cast<int>(state >> 27) - 16, 0, 255));
  }
  return g;
}

// Plug-in MI of the pairs minus the Miller–Madow bias (B_a − 1)(B_b − 1) / 2N.
double CorrectedMiOfPairs(const std::vector<std::pair<int, int>>& pairs, int bins) {
  std::vector<std::uint32_t> joint(static_cast<std::size_t>(bins * bins), 0);
  std::vector<bool> row_used(bins, false), col_used(bins, false);
  for (const auto& [a, b] : pairs) {
    ++joint[static_cast<std::size_t>(a * bins + b)];
    row_used[a] = true;
    col_used[b] = true;
  }
  const int ra = static_cast<int>(std::count(row_used.begin(), row_used.end(), true));
  const int cb = static_cast<int>(std::count(col_used.begin(), col_used.end(), true));
  return MutualInformation(joint, bins, bins) - (ra - 1) * (cb - 1) / (2.0 * static_cast<double>(pairs.size()));
}

TEST(SymmetryHeading, CurveMatchesADirectMutualInformation) {
  const Glance g = TexturedGlance();
  for (int bits = 1; bits <= 4; ++bits) {
    for (int half_width : {8, 12}) {
      for (bool significance : {false, true}) {
        HeadingOptions o;
        o.column_bits = bits;
        o.symmetry_half_width_px = half_width;
        o.symmetry_significance = significance;
        HeadingMeasureResult r;
        SymmetryHeading(o).Measure(Prepare(g, o), r);
        const int bins = 1 << bits;
        for (int x = o.symmetry_min_half_width_px; x <= kGlanceWidth - 1 - o.symmetry_min_half_width_px; ++x) {
          const int d_max = std::min({half_width, x, kGlanceWidth - 1 - x});
          std::vector<std::pair<int, int>> pairs;
          for (int v = 0; v < kGlanceHeight; ++v)
            for (int d = 1; d <= d_max; ++d) pairs.emplace_back(g.At(x - d, v) >> (8 - bits), g.At(x + d, v) >> (8 - bits));
          double expected = CorrectedMiOfPairs(pairs, bins);
          if (significance) expected *= static_cast<double>(d_max) / half_width;
          EXPECT_NEAR(r.curve[x], expected, 1e-5 * (1.0 + std::abs(expected)))
              << "bits " << bits << " half width " << half_width << " axis " << x;
        }
      }
    }
  }
}

TEST(VanishingHeading, CurveMatchesADirectMutualInformation) {
  const Glance g = TexturedGlance();
  constexpr int kSw = kGlanceWidth / 2, kSh = kGlanceHeight / 2;
  for (int bits = 1; bits <= 4; ++bits) {
    HeadingOptions o;
    o.vanishing_bits = bits;
    HeadingMeasureResult r;
    VanishingHeading(o).Measure(Prepare(g, o), r);  // no horizon: every row of offsets
    const int bins = 1 << bits, shift = 8 - bits;
    // Each column c shows the best score over the rows of the offset ox = ceil(c / 2).
    for (int c = 0; c < kGlanceWidth; ++c) {
      const int ox = (c + 1) / 2;
      double best = -1e30;
      for (int oy = 0; oy <= kGlanceHeight - kSh; ++oy) {
        std::vector<std::pair<int, int>> pairs;
        for (int j = 0; j < kSh; ++j)
          for (int i = 0; i < kSw; ++i) {
            const int mean = (g.At(2 * i, 2 * j) + g.At(2 * i + 1, 2 * j) + g.At(2 * i, 2 * j + 1) +
                              g.At(2 * i + 1, 2 * j + 1) + 2) >> 2;
            pairs.emplace_back(mean >> shift, g.At(ox + i, oy + j) >> shift);
          }
        best = std::max(best, CorrectedMiOfPairs(pairs, bins));
      }
      EXPECT_NEAR(r.curve[c], best, 1e-5 * (1.0 + std::abs(best))) << "bits " << bits << " column " << c;
    }
  }
}

}  // namespace
}  // namespace squint::corridor
