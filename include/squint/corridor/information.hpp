// Information-theoretic maths on small integer histograms: entropy (paper eq. 1), mutual
// information (eq. 2) and Jeffrey divergence (eq. 4). Natural logarithms (nats) throughout.
#pragma once

#include <cstdint>
#include <span>

namespace squint::corridor {

// Entropy of a histogram of counts, -Σ p log p; 0 for an empty histogram.
double Entropy(std::span<const std::uint32_t> counts);
double Entropy(std::span<const double> probabilities);

// Mutual information from a joint histogram of counts laid out row-major [bins_a × bins_b];
// 0 when empty. Preconditions: joint.size() == bins_a * bins_b.
double MutualInformation(std::span<const std::uint32_t> joint, int bins_a, int bins_b);

// Jeffrey divergence Σ (p - q) log(p / q) between two histograms (normalised here). Bins where
// exactly one histogram is empty would make it infinite, so both are smoothed by adding
// `epsilon` (a pseudo-count, in units of counts) to every bin first. Returns 0 for two empty
// histograms. Preconditions: equal sizes, epsilon > 0.
double JeffreyDivergence(std::span<const std::uint32_t> p, std::span<const std::uint32_t> q,
                         double epsilon = 0.5);
double JeffreyDivergence(std::span<const double> p, std::span<const double> q, double epsilon = 1e-6);

// n·log(n) for integer counts 0..kNLogNTableSize-1 (0 for n = 0), from a table built once;
// larger n is computed directly. Used by the glance kernels to avoid per-bin logarithms.
inline constexpr int kNLogNTableSize = 4096;
double NLogN(std::uint32_t n);
// The table itself (kNLogNTableSize entries), for kernels that hoist it out of their loops.
const double* NLogNTable();

// Entropy of a histogram of counts summing to `total`, using the n·log(n) table:
// H = log(N) - Σ n_i log n_i / N.
double EntropyFromCounts(const std::uint32_t* counts, int bins, std::uint32_t total);
// The same with log(total) given (kernels that call it many times with a few totals).
double EntropyFromCounts(const std::uint32_t* counts, int bins, std::uint32_t total, double log_total);

}  // namespace squint::corridor
