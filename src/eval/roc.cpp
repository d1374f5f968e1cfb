// ROC curve and AUC by sorting the scores once; ties handled as one step (diagonal segment).
#include "squint/eval/roc.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace squint::eval {

Roc ComputeRoc(std::span<const ScoredLabel> samples) {
  Roc roc;
  std::vector<ScoredLabel> sorted(samples.begin(), samples.end());
  // Descending score: lowering the threshold past each distinct score adds its samples.
  std::sort(sorted.begin(), sorted.end(), [](const ScoredLabel& a, const ScoredLabel& b) { return a.score > b.score; });
  for (const auto& s : sorted) (s.positive ? roc.positives : roc.negatives) += 1;
  const double P = static_cast<double>(std::max(1L, roc.positives));
  const double N = static_cast<double>(std::max(1L, roc.negatives));
  long tp = 0, fp = 0;
  // The strictest threshold: nothing above +inf, so only... start at (0, 0).
  roc.points.push_back({std::numeric_limits<double>::infinity(), 0.0, 0.0});
  double area = 0.0;
  std::size_t i = 0;
  while (i < sorted.size()) {
    const double score = sorted[i].score;
    const long tp0 = tp, fp0 = fp;
    while (i < sorted.size() && sorted[i].score == score) {
      (sorted[i].positive ? tp : fp) += 1;
      ++i;
    }
    // Trapezoid: ties give the diagonal, i.e. half credit.
    area += (fp - fp0) / N * 0.5 * (tp + tp0) / P;
    // Threshold just below this score: every sample with score >= it is positive.
    const double next = i < sorted.size() ? sorted[i].score : -std::numeric_limits<double>::infinity();
    const double threshold = std::isfinite(score) && std::isfinite(next) ? 0.5 * (score + next) : next;
    roc.points.push_back({threshold, fp / N, tp / P});
  }
  roc.auc = roc.Defined() ? area : 0.0;
  return roc;
}

Confusion ConfusionAt(std::span<const ScoredLabel> samples, double threshold) {
  Confusion c;
  for (const auto& s : samples) {
    const bool predicted = s.score > threshold;
    if (s.positive) (predicted ? c.tp : c.fn) += 1;
    else (predicted ? c.fp : c.tn) += 1;
  }
  return c;
}

}  // namespace squint::eval
