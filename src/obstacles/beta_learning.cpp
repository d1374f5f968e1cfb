// β learning by minimising FP + δ·FN (eq. 18) per zone, and the refinement band (§6.2).
#include "squint/obstacles/beta_learning.hpp"

#include <algorithm>
#include <cmath>

namespace squint::obstacles {

std::optional<double> OptimalBeta(const std::vector<LabelledDiscrepancy>& samples, double delta) {
  if (samples.empty()) return std::nullopt;
  std::vector<std::pair<double, bool>> sorted;
  sorted.reserve(samples.size());
  for (const auto& s : samples) sorted.emplace_back(s.discrepancy_m, s.obstacle);
  std::sort(sorted.begin(), sorted.end());
  // β below every D: every feature is an obstacle, FP = all ground points, FN = 0.
  double fp = 0.0, fn = 0.0;
  for (const auto& [d, obstacle] : sorted) fp += obstacle ? 0.0 : 1.0;
  double best_cost = fp;
  std::size_t best_end = 0;  // number of sorted samples at or below β
  std::size_t i = 0;
  while (i < sorted.size()) {
    // Move every sample of this D value below the threshold together.
    const double d = sorted[i].first;
    while (i < sorted.size() && sorted[i].first == d) {
      if (sorted[i].second) fn += 1.0;
      else fp -= 1.0;
      ++i;
    }
    const double cost = fp + delta * fn;
    if (cost < best_cost - 1e-12) {
      best_cost = cost;
      best_end = i;
    }
  }
  // β halfway between the last sample called ground and the first called obstacle (the widest
  // margin among the equally good thresholds).
  if (best_end == 0) return std::max(0.0, sorted.front().first * 0.5);
  if (best_end == sorted.size()) return sorted.back().first;
  return 0.5 * (sorted[best_end - 1].first + sorted[best_end].first);
}

std::optional<std::pair<double, double>> OptimalBand(const std::vector<LabelledDiscrepancy>& samples, double delta,
                                                     double unclassified_cost) {
  if (samples.empty()) return std::nullopt;
  std::vector<std::pair<double, bool>> sorted;
  sorted.reserve(samples.size());
  for (const auto& s : samples) sorted.emplace_back(s.discrepancy_m, s.obstacle);
  std::sort(sorted.begin(), sorted.end());
  // Cut positions k = 0..n (k samples at or below the cut), only between distinct D values.
  const std::size_t n = sorted.size();
  std::vector<std::size_t> cuts = {0};
  for (std::size_t i = 1; i <= n; ++i)
    if (i == n || sorted[i].first != sorted[i - 1].first) cuts.push_back(i);
  std::vector<double> obstacles_below(n + 1, 0.0), ground_below(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    obstacles_below[i + 1] = obstacles_below[i] + (sorted[i].second ? 1.0 : 0.0);
    ground_below[i + 1] = ground_below[i] + (sorted[i].second ? 0.0 : 1.0);
  }
  const double ground_total = ground_below[n];
  // cost(lo, hi) = [δ FN(lo) − λ k_lo] + [λ k_hi + FP(hi)]: for each hi keep the best lo <= hi.
  double best_cost = INFINITY, best_left = INFINITY;
  std::size_t best_lo = 0, best_hi = 0, left_arg = 0;
  for (std::size_t k : cuts) {
    const double left = delta * obstacles_below[k] - unclassified_cost * static_cast<double>(k);
    if (left < best_left - 1e-12) best_left = left, left_arg = k;
    const double right = unclassified_cost * static_cast<double>(k) + (ground_total - ground_below[k]);
    if (best_left + right < best_cost - 1e-12) best_cost = best_left + right, best_lo = left_arg, best_hi = k;
  }
  // Thresholds halfway between neighbouring samples (as OptimalBeta).
  auto threshold = [&](std::size_t k) {
    if (k == 0) return std::max(0.0, sorted.front().first * 0.5);
    if (k == n) return sorted.back().first;
    return 0.5 * (sorted[k - 1].first + sorted[k].first);
  };
  return std::make_pair(threshold(best_lo), threshold(best_hi));
}

ClassifierOptions LearnZoneThresholds(const std::vector<LabelledDiscrepancy>& samples,
                                      const BetaLearningOptions& options, const ClassifierOptions& base) {
  ClassifierOptions out = base;
  const std::optional<double> pooled = OptimalBeta(samples, options.delta);
  for (int z = 0; z < 3; ++z) {
    std::vector<LabelledDiscrepancy> zone;
    for (const auto& s : samples)
      if (s.zone == z) zone.push_back(s);
    ZoneThreshold& t = out.zones[static_cast<std::size_t>(z)];
    std::optional<double> beta;
    if (static_cast<int>(zone.size()) >= options.min_zone_samples) beta = OptimalBeta(zone, options.delta);
    if (!beta) beta = pooled;
    if (beta) t.beta_m = *beta;
    t.refine_high_m.reset();
    if (!options.refine_zone[static_cast<std::size_t>(z)]) continue;
    if (!options.band_from_false_positive_quantile) {
      if (static_cast<int>(zone.size()) < options.min_zone_samples) continue;
      const auto band = OptimalBand(zone, options.delta, options.unclassified_cost);
      if (!band) continue;
      t.beta_m = band->first;
      if (band->second > band->first) t.refine_high_m = band->second;
      continue;
    }
    std::vector<double> false_positive_d;
    for (const auto& s : zone)
      if (!s.obstacle && s.discrepancy_m > t.beta_m) false_positive_d.push_back(s.discrepancy_m);
    if (false_positive_d.empty()) continue;
    std::sort(false_positive_d.begin(), false_positive_d.end());
    const double q = std::clamp(options.refine_quantile, 0.0, 1.0);
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(false_positive_d.size()))) ;
    t.refine_high_m = false_positive_d[std::min(false_positive_d.size() - 1, k == 0 ? 0 : k - 1)];
  }
  return out;
}

}  // namespace squint::obstacles
