// Accuracy metrics for estimates against ground truth: RMSE, coverage, per-bin mean ± 2σ and
// sign agreement (the exploration paper's Figs. 8–10), and histograms.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace squint::eval {

// One estimate beside its truth; `estimate` is empty when the estimator gave no answer.
struct Sample {
  double truth = 0.0;
  std::optional<double> estimate;
};

// Error statistics over the samples that have an estimate.
struct ErrorSummary {
  std::size_t frames = 0;     // samples considered (with or without an estimate)
  std::size_t estimated = 0;  // samples with an estimate
  double coverage = 0.0;      // estimated / frames (0 when there are no frames)
  double rmse = 0.0;          // sqrt(mean((estimate - truth)^2)); 0 when nothing was estimated
  double mean_error = 0.0;    // mean(estimate - truth)
  double std_error = 0.0;     // population standard deviation of (estimate - truth)
  double max_abs_error = 0.0;
};

ErrorSummary Summarize(std::span<const Sample> samples);
// Only the samples whose truth lies in [truth_min, truth_max].
ErrorSummary SummarizeRange(std::span<const Sample> samples, double truth_min, double truth_max);

// Root mean square of a set of errors; 0 for an empty set.
double Rmse(std::span<const double> errors);

// Statistics of the samples whose truth falls into one bin [lo, hi).
struct BinStats {
  double lo = 0.0;
  double hi = 0.0;
  double centre = 0.0;
  std::size_t frames = 0;          // samples whose truth is in the bin
  std::size_t estimated = 0;       // ... of which have an estimate
  double mean_estimate = 0.0;      // over the estimated samples
  double std_estimate = 0.0;       // population σ of the estimates (the ±2σ bars of Figs. 8, 10)
  double rmse = 0.0;               // of estimate - truth
  double mean_truth = 0.0;         // over all samples in the bin
  // Fraction of estimated samples with sign(estimate) == sign(truth) (Fig. 9); samples whose
  // truth is exactly 0 have no right sign and are left out, so `signed_frames` may be smaller.
  std::size_t signed_frames = 0;
  double right_sign_fraction = 0.0;
};

// Bins of width `bin_width` aligned so that bin k covers [origin + k w, origin + (k + 1) w).
// Only non-empty bins are returned, in increasing order. `bin_width` must be positive.
std::vector<BinStats> BinByTruth(std::span<const Sample> samples, double bin_width, double origin);

// Sign agreement over the estimated samples with |truth| >= min_abs_truth.
struct SignSummary {
  std::size_t frames = 0;  // estimated samples with |truth| >= min_abs_truth (and truth != 0)
  std::size_t right = 0;
  double fraction = 0.0;  // right / frames; 0 when frames == 0
};
SignSummary SignAgreement(std::span<const Sample> samples, double min_abs_truth);

// A histogram over [lo, hi) with `bins` equal bins; values outside land in the first/last bin
// (counted in `underflow`/`overflow` too so that a reader can tell).
struct Histogram {
  double lo = 0.0;
  double hi = 0.0;
  std::vector<std::size_t> counts;
  std::size_t underflow = 0;
  std::size_t overflow = 0;
};
Histogram MakeHistogram(std::span<const double> values, double lo, double hi, int bins);

// Number of `true` entries in each consecutive block of `block` flags (the last block may be
// shorter). Fig. 13 middle: frames fully processed per 50-frame bin.
std::vector<std::size_t> CountPerBlock(const std::vector<bool>& flags, std::size_t block);

}  // namespace squint::eval
