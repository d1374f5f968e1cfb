// Learning the threshold β from labelled features by minimising FP(β) + δ·FN(β) (paper eq. 18),
// per zone, and the refinement band of §6.2.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "squint/obstacles/classifier.hpp"

namespace squint::obstacles {

// One labelled feature below the horizon: its zone (0–2), its D and whether it truly stands above
// the floor (ground truth from a label mask).
struct LabelledDiscrepancy {
  int zone = 0;
  double discrepancy_m = 0.0;
  bool obstacle = false;
};

struct BetaLearningOptions {
  double delta = 0.5;  // weight of false negatives (eq. 18)
  // Zones that get a refinement band (β, refine_high]: features with D inside are not classified.
  // The paper sets it by hand in zone 1 ("all FP of zone 1 presented D in 20–85 mm"); here the band
  // is learned in every zone by minimising FP + δ·FN + λ·U, U the features left unclassified
  // (FromFalsePositiveQuantile = false), or, as the paper, from the D of the false positives above β
  // (its refine_quantile quantile; FromFalsePositiveQuantile = true).
  std::array<bool, 3> refine_zone = {true, true, true};
  bool band_from_false_positive_quantile = false;
  double refine_quantile = 0.9;
  // λ: the cost of leaving a feature unclassified, relative to one false positive.
  double unclassified_cost = 0.15;
  // A zone with fewer samples than this keeps the pooled (all zones) β.
  int min_zone_samples = 20;
};

// The β minimising FP + δ·FN over samples (ties: the smallest such β). Obstacle when D > β.
// None when there are no samples.
std::optional<double> OptimalBeta(const std::vector<LabelledDiscrepancy>& samples, double delta);

// The band (lo, hi] minimising FP(D > hi) + δ·FN(D <= lo) + λ·#(lo < D <= hi), lo <= hi. None
// without samples. lo == hi means no band.
std::optional<std::pair<double, double>> OptimalBand(const std::vector<LabelledDiscrepancy>& samples, double delta,
                                                     double unclassified_cost);

// β for each zone and the refinement bands, starting from `base` (zoning, flags are kept).
ClassifierOptions LearnZoneThresholds(const std::vector<LabelledDiscrepancy>& samples,
                                      const BetaLearningOptions& options, const ClassifierOptions& base);

}  // namespace squint::obstacles
