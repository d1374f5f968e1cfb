// Entropy, mutual information and Jeffrey divergence against values computed by hand.
#include "squint/corridor/information.hpp"
#include "squint/corridor/prepared_glance.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace squint::corridor {
namespace {

constexpr double kTol = 1e-12;

TEST(Entropy, HandComputedValues) {
  // Two equal bins: log 2. Four equal bins: log 4. [2, 1, 1]: -(.5 log .5 + 2 · .25 log .25) = 1.5 log 2.
  const std::array<std::uint32_t, 2> two = {5, 5};
  const std::array<std::uint32_t, 4> four = {3, 3, 3, 3};
  const std::array<std::uint32_t, 3> mixed = {2, 1, 1};
  EXPECT_NEAR(Entropy(two), std::log(2.0), kTol);
  EXPECT_NEAR(Entropy(four), std::log(4.0), kTol);
  EXPECT_NEAR(Entropy(mixed), 1.5 * std::log(2.0), kTol);
  // The n·log n table version agrees.
  EXPECT_NEAR(EntropyFromCounts(mixed.data(), 3, 4), 1.5 * std::log(2.0), 1e-12);
  const std::array<double, 3> p = {0.5, 0.25, 0.25};
  EXPECT_NEAR(Entropy(p), 1.5 * std::log(2.0), kTol);
}

TEST(Entropy, DegenerateHistograms) {
  const std::array<std::uint32_t, 3> empty = {0, 0, 0};
  const std::array<std::uint32_t, 3> single = {0, 9, 0};
  EXPECT_EQ(Entropy(empty), 0.0);
  EXPECT_EQ(Entropy(single), 0.0);
  EXPECT_EQ(EntropyFromCounts(single.data(), 3, 9), 0.0);
  EXPECT_EQ(EntropyFromCounts(empty.data(), 3, 0), 0.0);
}

TEST(MutualInformation, IdenticalAndIndependentVariables) {
  // a == b, uniform over 2 values: MI = H = log 2.
  const std::array<std::uint32_t, 4> same = {4, 0, 0, 4};
  EXPECT_NEAR(MutualInformation(same, 2, 2), std::log(2.0), kTol);
  // Independent: the joint is the product of the marginals: MI = 0.
  const std::array<std::uint32_t, 4> independent = {2, 6, 1, 3};  // rows 8 and 4, columns 3 and 9 (of 12)
  EXPECT_NEAR(MutualInformation(independent, 2, 2), 0.0, 1e-12);
  const std::array<std::uint32_t, 4> empty = {0, 0, 0, 0};
  EXPECT_EQ(MutualInformation(empty, 2, 2), 0.0);
}

TEST(MutualInformation, HandComputedAsymmetricJoint) {
  // Joint [[2, 1], [0, 1]] / 4: p(0,0)=.5, p(0,1)=.25, p(1,1)=.25; pa = (.75, .25), pb = (.5, .5).
  // MI = .5 log(.5/.375) + .25 log(.25/.375) + .25 log(.25/.125).
  const std::array<std::uint32_t, 4> joint = {2, 1, 0, 1};
  const double expected = 0.5 * std::log(0.5 / 0.375) + 0.25 * std::log(0.25 / 0.375) + 0.25 * std::log(2.0);
  EXPECT_NEAR(MutualInformation(joint, 2, 2), expected, kTol);
}

TEST(JeffreyDivergence, HandComputedValue) {
  // p = (.5, .5), q = (.25, .75): J = (.25) log 2 + (-.25) log(2/3) = .25 log 3.
  const std::array<double, 2> p = {0.5, 0.5};
  const std::array<double, 2> q = {0.25, 0.75};
  EXPECT_NEAR(JeffreyDivergence(p, q, 1e-15), 0.25 * std::log(3.0), 1e-12);
  // Symmetric, zero for equal histograms.
  EXPECT_NEAR(JeffreyDivergence(q, p, 1e-15), JeffreyDivergence(p, q, 1e-15), 1e-15);
  EXPECT_NEAR(JeffreyDivergence(p, p, 1e-15), 0.0, 1e-15);
}

TEST(JeffreyDivergence, CountsAreNormalisedAndEmptyBinsStayFinite) {
  // Counts (2, 2) vs (1, 3) are the distributions above; a tiny pseudo-count barely moves it.
  const std::array<std::uint32_t, 2> p = {2, 2};
  const std::array<std::uint32_t, 2> q = {1, 3};
  EXPECT_NEAR(JeffreyDivergence(p, q, 1e-9), 0.25 * std::log(3.0), 1e-8);
  // Disjoint supports would be infinite without smoothing; with it the value is finite and large.
  const std::array<std::uint32_t, 2> a = {10, 0};
  const std::array<std::uint32_t, 2> b = {0, 10};
  const double j = JeffreyDivergence(a, b);
  EXPECT_TRUE(std::isfinite(j));
  EXPECT_GT(j, 3.0);
  const std::array<std::uint32_t, 2> zero = {0, 0};
  EXPECT_EQ(JeffreyDivergence(zero, zero), 0.0);
}

TEST(NLogN, TableMatchesDirectComputation) {
  for (std::uint32_t n : {0u, 1u, 2u, 7u, 768u, 4095u, 4096u, 100000u}) {
    const double expected = n == 0 ? 0.0 : n * std::log(static_cast<double>(n));
    EXPECT_NEAR(NLogN(n), expected, 1e-9 * std::max(1.0, expected)) << n;
  }
}

TEST(WholeGlanceHistogram, EntropyAndCountsAtEveryBitDepth) {
  // Grey levels 0, 64, 128, 192 on 1/2, 1/4, 1/8, 1/8 of the pixels: at 2 or more bits they are
  // four bins, entropy 1.75 log 2; at 1 bit, two bins of 3/4 and 1/4.
  Glance g;
  for (int i = 0; i < kGlancePixels; ++i) {
    const int k = i % 8;
    g.pixels[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(k < 4 ? 0 : k < 6 ? 64 : k < 7 ? 128 : 192);
  }
  for (int bits = 1; bits <= 8; ++bits) {
    PreparedGlance out;
    ComputeHistogramAndEntropy(g, bits, out);
    ASSERT_EQ(out.image_bins, 1 << bits);
    std::uint32_t total = 0;
    for (int b = 0; b < out.image_bins; ++b) total += out.histogram[static_cast<std::size_t>(b)];
    EXPECT_EQ(total, static_cast<std::uint32_t>(kGlancePixels)) << bits;
    const double expected = bits == 1 ? -(0.75 * std::log(0.75) + 0.25 * std::log(0.25)) : 1.75 * std::log(2.0);
    EXPECT_NEAR(out.entropy, expected, 1e-12) << bits;
    EXPECT_EQ(out.histogram[0], static_cast<std::uint32_t>(bits == 1 ? 576 : 384)) << bits;
    EXPECT_EQ(out.min_level, 0);
    EXPECT_EQ(out.max_level, 192);
    EXPECT_FALSE(out.Uniform());
  }
  // A uniform glance: one full bin, entropy exactly 0 (never -1e-16).
  Glance flat;
  flat.pixels.fill(77);
  PreparedGlance out;
  ComputeHistogramAndEntropy(flat, 6, out);
  EXPECT_EQ(out.entropy, 0.0);
  EXPECT_TRUE(out.Uniform());
  EXPECT_EQ(out.histogram[77 >> 2], static_cast<std::uint32_t>(kGlancePixels));
}

}  // namespace
}  // namespace squint::corridor
