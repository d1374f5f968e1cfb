// β learning (eq. 18) recovers planted thresholds; the classifier applies zones and refinement.
#include "squint/obstacles/beta_learning.hpp"

#include <gtest/gtest.h>

#include <random>

namespace squint::obstacles {
namespace {

TEST(BetaLearning, HandComputedCostsPickTheMinimum) {
  // Ground at 0.1 and 0.3, obstacle at 0.2. β below all: FP 2 -> cost 2; β in [0.1, 0.2): FP 1 ->
  // 1; β in [0.2, 0.3): FP 1 + δ FN 1; β >= 0.3: δ FN 1.
  const std::vector<LabelledDiscrepancy> s = {{0, 0.1, false}, {0, 0.2, true}, {0, 0.3, false}};
  EXPECT_DOUBLE_EQ(*OptimalBeta(s, 0.5), 0.3);           // cost 0.5 beats 1
  EXPECT_DOUBLE_EQ(*OptimalBeta(s, 2.0), 0.15);          // cost 1 (mid-gap) beats 2
  EXPECT_FALSE(OptimalBeta({}, 0.5).has_value());
}

TEST(BetaLearning, RecoversAPlantedThresholdPerZone) {
  std::mt19937 rng(7);
  const double planted[3] = {0.021, 0.045, 0.120};
  std::vector<LabelledDiscrepancy> samples;
  for (int z = 0; z < 3; ++z) {
    std::uniform_real_distribution<double> ground(0.0, planted[z]), obstacle(planted[z], 4.0 * planted[z]);
    for (int i = 0; i < 400; ++i) samples.push_back({z, ground(rng), false});
    for (int i = 0; i < 200; ++i) samples.push_back({z, obstacle(rng), true});
  }
  BetaLearningOptions opt;
  opt.refine_zone = {false, false, false};  // plain β per zone
  const ClassifierOptions learned = LearnZoneThresholds(samples, opt, ClassifierOptions{});
  for (int z = 0; z < 3; ++z) {
    // With 400 uniform ground samples, the largest lies within ~1% of the planted threshold and the
    // learned β sits between it and the smallest obstacle D.
    EXPECT_NEAR(learned.zones[static_cast<std::size_t>(z)].beta_m, planted[z], 0.02 * planted[z]) << "zone " << z;
    EXPECT_FALSE(learned.zones[static_cast<std::size_t>(z)].refine_high_m.has_value());
  }
}

TEST(BetaLearning, OverlapIsResolvedByTheFalseNegativeWeight) {
  // Ground D uniform on [0, 2], obstacle D uniform on [1, 3], same counts. In the overlap a β
  // raises FN at rate 1 and lowers FP at rate 1 (per unit D, per sample density), so with δ < 1 the
  // cost falls until the ground runs out: β -> 2. With δ > 1 it rises from the start: β -> 1.
  std::vector<LabelledDiscrepancy> s;
  for (int i = 0; i <= 1000; ++i) {
    s.push_back({0, 2.0 * i / 1000.0, false});
    s.push_back({0, 1.0 + 2.0 * i / 1000.0, true});
  }
  EXPECT_NEAR(*OptimalBeta(s, 0.5), 2.0, 0.01);
  EXPECT_NEAR(*OptimalBeta(s, 2.0), 1.0, 0.01);
}

TEST(BetaLearning, RefinementBandCoversTheFalsePositives) {
  std::vector<LabelledDiscrepancy> s;
  // Ground D in [0, 0.03), six ground outliers at 0.10–0.30 (mirror images, say), obstacles at
  // 0.05–1.04. Raising β over the outliers would cost 0.5 × 26 obstacles > 6 FP, so β stays low and
  // the outliers must fall in the refinement band.
  for (int i = 0; i < 100; ++i) s.push_back({1, 0.0003 * i, false});
  for (int i = 0; i < 6; ++i) s.push_back({1, 0.10 + 0.04 * i, false});
  for (int i = 0; i < 100; ++i) s.push_back({1, 0.05 + 0.01 * i, true});
  BetaLearningOptions opt;
  opt.refine_quantile = 1.0;
  opt.band_from_false_positive_quantile = true;
  opt.min_zone_samples = 10;
  const ClassifierOptions c = LearnZoneThresholds(s, opt, ClassifierOptions{});
  const ZoneThreshold& t = c.zones[1];
  EXPECT_GT(t.beta_m, 0.03);
  EXPECT_LT(t.beta_m, 0.05);
  ASSERT_TRUE(t.refine_high_m.has_value());
  // Every ground point above β lies inside the band.
  for (const auto& x : s) {
    if (!x.obstacle && x.discrepancy_m > t.beta_m) {
      EXPECT_LE(x.discrepancy_m, *t.refine_high_m + 1e-12);
    }
  }
}

TEST(BetaLearning, LearnedBandLeavesTheOverlapUnclassified) {
  // Ground D uniform on [0, 2], obstacles on [1, 3] (about 500 of each per unit D). Inside the
  // overlap, lowering lo by dD saves δ·500 dD of FN and costs λ·1000 dD of unclassified features;
  // raising hi saves 500 dD of FP for the same λ·1000 dD. With λ = 0.2 (< δ/2) both ends move out
  // to the overlap's ends: the band is (1, 2].
  std::vector<LabelledDiscrepancy> s;
  for (int i = 0; i <= 1000; ++i) {
    s.push_back({0, 2.0 * i / 1000.0, false});
    s.push_back({0, 1.0 + 2.0 * i / 1000.0, true});
  }
  const auto band = OptimalBand(s, 0.5, 0.2);
  ASSERT_TRUE(band.has_value());
  EXPECT_NEAR(band->first, 1.0, 0.01);
  EXPECT_NEAR(band->second, 2.0, 0.01);
  // λ = 0.6 > 0.5: the band shrinks to nothing and lo = hi is OptimalBeta's β.
  const auto none = OptimalBand(s, 0.5, 0.6);
  EXPECT_NEAR(none->first, none->second, 1e-12);
  EXPECT_NEAR(none->first, *OptimalBeta(s, 0.5), 0.01);
}

TEST(Classifier, ZonesBetasAndRefinement) {
  ClassifierOptions c;
  c.zones[0] = {0.02, std::nullopt};
  c.zones[1] = {0.03, 0.08};
  c.zones[2] = {0.10, std::nullopt};
  EXPECT_EQ(ClassifyFeature(3, std::nullopt, c), FeatureClass::kObstacle);  // above the horizon
  EXPECT_EQ(ClassifyFeature(0, 0.019, c), FeatureClass::kGround);
  EXPECT_EQ(ClassifyFeature(0, 0.021, c), FeatureClass::kObstacle);
  EXPECT_EQ(ClassifyFeature(1, 0.029, c), FeatureClass::kGround);
  EXPECT_FALSE(ClassifyFeature(1, 0.05, c).has_value());  // inside the refinement band
  EXPECT_EQ(ClassifyFeature(1, 0.09, c), FeatureClass::kObstacle);
  EXPECT_EQ(ClassifyFeature(2, 0.09, c), FeatureClass::kGround);
  c.refinement = false;
  EXPECT_EQ(ClassifyFeature(1, 0.05, c), FeatureClass::kObstacle);
  c.zone_beta = false;  // one β = zones[0].beta_m everywhere
  EXPECT_EQ(ClassifyFeature(2, 0.09, c), FeatureClass::kObstacle);
  EXPECT_EQ(ClassifyFeature(1, 0.01, c), FeatureClass::kGround);
}

}  // namespace
}  // namespace squint::obstacles
