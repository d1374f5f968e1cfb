// ROC analysis of a score against binary truth: the curve (recall vs fall-out, eq. 17), its area
// (AUC), and the confusion counts at a threshold. Positive = obstacle; predicted positive when
// score > threshold (as eq. 4: obstacle when D > β).
#pragma once

#include <span>
#include <vector>

namespace squint::eval {

struct ScoredLabel {
  double score = 0.0;  // may be +infinity (always positive, e.g. above the horizon)
  bool positive = false;
};

struct Confusion {
  long tp = 0, fp = 0, tn = 0, fn = 0;
  long Positives() const { return tp + fn; }
  long Negatives() const { return fp + tn; }
  // TP / (TP + FN); 0 without positives.
  double Recall() const { return Positives() > 0 ? static_cast<double>(tp) / Positives() : 0.0; }
  // FP / (FP + TN); 0 without negatives.
  double FallOut() const { return Negatives() > 0 ? static_cast<double>(fp) / Negatives() : 0.0; }
  Confusion& operator+=(const Confusion& o) {
    tp += o.tp, fp += o.fp, tn += o.tn, fn += o.fn;
    return *this;
  }
};

struct RocPoint {
  double threshold = 0.0;  // predicted positive when score > threshold
  double fall_out = 0.0;
  double recall = 0.0;
};

struct Roc {
  // From (1, 1) (threshold below every score) to (0, 0) or to the fall-out/recall of the
  // always-positive scores; one point per distinct score.
  std::vector<RocPoint> points;
  double auc = 0.0;  // area under the curve; ties count one half (Mann–Whitney)
  long positives = 0;
  long negatives = 0;
  // AUC is meaningful only with both classes present.
  bool Defined() const { return positives > 0 && negatives > 0; }
};

Roc ComputeRoc(std::span<const ScoredLabel> samples);
Confusion ConfusionAt(std::span<const ScoredLabel> samples, double threshold);

}  // namespace squint::eval
