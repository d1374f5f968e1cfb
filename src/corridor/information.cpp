// Entropy, mutual information and Jeffrey divergence on histograms (paper eqs. 1, 2, 4).
#include "squint/corridor/information.hpp"

#include <array>
#include <cmath>
#include <numeric>

#include "squint/core/error.hpp"

namespace squint::corridor {
const double* NLogNTable() {
  static const std::array<double, kNLogNTableSize> table = [] {
    std::array<double, kNLogNTableSize> t{};
    for (int n = 1; n < kNLogNTableSize; ++n) t[n] = n * std::log(static_cast<double>(n));
    return t;
  }();
  return table.data();
}

double NLogN(std::uint32_t n) {
  if (n < static_cast<std::uint32_t>(kNLogNTableSize)) return NLogNTable()[n];
  const double x = static_cast<double>(n);
  return x * std::log(x);
}

double EntropyFromCounts(const std::uint32_t* counts, int bins, std::uint32_t total) {
  if (total == 0) return 0.0;
  return EntropyFromCounts(counts, bins, total, std::log(static_cast<double>(total)));
}

double EntropyFromCounts(const std::uint32_t* counts, int bins, std::uint32_t total, double log_total) {
  if (total == 0) return 0.0;
  const double* table = NLogNTable();
  double sum = 0.0;
  for (int i = 0; i < bins; ++i) {
    const std::uint32_t c = counts[i];
    sum += c < static_cast<std::uint32_t>(kNLogNTableSize) ? table[c] : NLogN(c);
  }
  const double h = log_total - sum / total;
  return h > 0.0 ? h : 0.0;  // rounding can give -1e-16 for a single full bin
}

double Entropy(std::span<const std::uint32_t> counts) {
  const std::uint64_t total = std::accumulate(counts.begin(), counts.end(), std::uint64_t{0});
  if (total == 0) return 0.0;
  double h = 0.0;
  for (std::uint32_t c : counts) {
    if (c == 0) continue;
    const double p = static_cast<double>(c) / static_cast<double>(total);
    h -= p * std::log(p);
  }
  return h;
}

double Entropy(std::span<const double> probabilities) {
  double total = 0.0;
  for (double p : probabilities) total += p;
  if (!(total > 0.0)) return 0.0;
  double h = 0.0;
  for (double p : probabilities) {
    if (p <= 0.0) continue;
    const double q = p / total;
    h -= q * std::log(q);
  }
  return h;
}

double MutualInformation(std::span<const std::uint32_t> joint, int bins_a, int bins_b) {
  SQUINT_ENSURE(bins_a > 0 && bins_b > 0 && joint.size() == static_cast<std::size_t>(bins_a * bins_b),
                "joint histogram size must be bins_a * bins_b");
  std::uint64_t total = 0;
  for (std::uint32_t c : joint) total += c;
  if (total == 0) return 0.0;
  // MI = Σ p(a,b) log(p(a,b) / (p(a) p(b))), with marginals accumulated on the fly.
  double mi = 0.0;
  const double n = static_cast<double>(total);
  for (int a = 0; a < bins_a; ++a) {
    std::uint64_t row = 0;
    for (int b = 0; b < bins_b; ++b) row += joint[a * bins_b + b];
    if (row == 0) continue;
    for (int b = 0; b < bins_b; ++b) {
      const std::uint32_t c = joint[a * bins_b + b];
      if (c == 0) continue;
      std::uint64_t col = 0;
      for (int k = 0; k < bins_a; ++k) col += joint[k * bins_b + b];
      mi += (c / n) * std::log((c * n) / (static_cast<double>(row) * static_cast<double>(col)));
    }
  }
  return mi > 0.0 ? mi : 0.0;
}

double JeffreyDivergence(std::span<const double> p, std::span<const double> q, double epsilon) {
  SQUINT_ENSURE(p.size() == q.size(), "Jeffrey divergence needs histograms of equal size");
  SQUINT_ENSURE(epsilon > 0.0, "Jeffrey divergence needs epsilon > 0");
  double sp = 0.0, sq = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    sp += p[i] + epsilon;
    sq += q[i] + epsilon;
  }
  double j = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double a = (p[i] + epsilon) / sp;
    const double b = (q[i] + epsilon) / sq;
    j += (a - b) * std::log(a / b);  // eq. 4: p log(p/q) + q log(q/p)
  }
  return j;
}

double JeffreyDivergence(std::span<const std::uint32_t> p, std::span<const std::uint32_t> q, double epsilon) {
  SQUINT_ENSURE(p.size() == q.size(), "Jeffrey divergence needs histograms of equal size");
  SQUINT_ENSURE(epsilon > 0.0, "Jeffrey divergence needs epsilon > 0");
  std::uint64_t tp = 0, tq = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    tp += p[i];
    tq += q[i];
  }
  if (tp == 0 && tq == 0) return 0.0;
  const double sp = static_cast<double>(tp) + epsilon * static_cast<double>(p.size());
  const double sq = static_cast<double>(tq) + epsilon * static_cast<double>(q.size());
  double j = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] == 0 && q[i] == 0 && tp == tq) continue;  // equal smoothed probabilities: no term
    const double a = (p[i] + epsilon) / sp;
    const double b = (q[i] + epsilon) / sq;
    j += (a - b) * std::log(a / b);
  }
  return j;
}

}  // namespace squint::corridor
