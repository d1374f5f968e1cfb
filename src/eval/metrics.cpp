// Accuracy metrics for estimates against ground truth (see metrics.hpp).
#include "squint/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "squint/core/error.hpp"

namespace squint::eval {

double Rmse(std::span<const double> errors) {
  if (errors.empty()) return 0.0;
  double sum = 0.0;
  for (double e : errors) sum += e * e;
  return std::sqrt(sum / static_cast<double>(errors.size()));
}

namespace {

ErrorSummary SummarizeIf(std::span<const Sample> samples, double lo, double hi) {
  ErrorSummary s;
  double sum = 0.0, sum2 = 0.0;
  for (const Sample& x : samples) {
    if (x.truth < lo || x.truth > hi) continue;
    ++s.frames;
    if (!x.estimate) continue;
    const double e = *x.estimate - x.truth;
    ++s.estimated;
    sum += e;
    sum2 += e * e;
    s.max_abs_error = std::max(s.max_abs_error, std::abs(e));
  }
  if (s.frames > 0) s.coverage = static_cast<double>(s.estimated) / static_cast<double>(s.frames);
  if (s.estimated > 0) {
    const double n = static_cast<double>(s.estimated);
    s.mean_error = sum / n;
    s.rmse = std::sqrt(sum2 / n);
    s.std_error = std::sqrt(std::max(0.0, sum2 / n - s.mean_error * s.mean_error));
  }
  return s;
}

int Sign(double v) { return (v > 0.0) - (v < 0.0); }

}  // namespace

ErrorSummary Summarize(std::span<const Sample> samples) {
  return SummarizeIf(samples, -HUGE_VAL, HUGE_VAL);
}

ErrorSummary SummarizeRange(std::span<const Sample> samples, double truth_min, double truth_max) {
  return SummarizeIf(samples, truth_min, truth_max);
}

std::vector<BinStats> BinByTruth(std::span<const Sample> samples, double bin_width, double origin) {
  SQUINT_ENSURE(bin_width > 0.0, "bin width must be positive");
  struct Acc {
    std::size_t frames = 0, estimated = 0, signed_frames = 0, right = 0;
    double sum_est = 0, sum_est2 = 0, sum_err2 = 0, sum_truth = 0;
  };
  std::map<long long, Acc> bins;
  for (const Sample& x : samples) {
    const long long k = static_cast<long long>(std::floor((x.truth - origin) / bin_width));
    Acc& a = bins[k];
    ++a.frames;
    a.sum_truth += x.truth;
    if (!x.estimate) continue;
    ++a.estimated;
    a.sum_est += *x.estimate;
    a.sum_est2 += *x.estimate * *x.estimate;
    const double e = *x.estimate - x.truth;
    a.sum_err2 += e * e;
    if (Sign(x.truth) != 0) {
      ++a.signed_frames;
      if (Sign(*x.estimate) == Sign(x.truth)) ++a.right;
    }
  }
  std::vector<BinStats> out;
  out.reserve(bins.size());
  for (const auto& [k, a] : bins) {
    BinStats b;
    b.lo = origin + static_cast<double>(k) * bin_width;
    b.hi = b.lo + bin_width;
    b.centre = 0.5 * (b.lo + b.hi);
    b.frames = a.frames;
    b.estimated = a.estimated;
    b.mean_truth = a.sum_truth / static_cast<double>(a.frames);
    if (a.estimated > 0) {
      const double n = static_cast<double>(a.estimated);
      b.mean_estimate = a.sum_est / n;
      b.std_estimate = std::sqrt(std::max(0.0, a.sum_est2 / n - b.mean_estimate * b.mean_estimate));
      b.rmse = std::sqrt(a.sum_err2 / n);
    }
    b.signed_frames = a.signed_frames;
    if (a.signed_frames > 0) b.right_sign_fraction = static_cast<double>(a.right) / static_cast<double>(a.signed_frames);
    out.push_back(b);
  }
  return out;
}

SignSummary SignAgreement(std::span<const Sample> samples, double min_abs_truth) {
  SignSummary s;
  for (const Sample& x : samples) {
    if (!x.estimate || Sign(x.truth) == 0 || std::abs(x.truth) < min_abs_truth) continue;
    ++s.frames;
    if (Sign(*x.estimate) == Sign(x.truth)) ++s.right;
  }
  if (s.frames > 0) s.fraction = static_cast<double>(s.right) / static_cast<double>(s.frames);
  return s;
}

Histogram MakeHistogram(std::span<const double> values, double lo, double hi, int bins) {
  SQUINT_ENSURE(bins > 0 && hi > lo, "histogram needs bins > 0 and hi > lo");
  Histogram h;
  h.lo = lo;
  h.hi = hi;
  h.counts.assign(static_cast<std::size_t>(bins), 0);
  const double w = (hi - lo) / bins;
  for (double v : values) {
    long long k = static_cast<long long>(std::floor((v - lo) / w));
    if (v < lo) {
      ++h.underflow;
      k = 0;
    } else if (k >= bins) {
      ++h.overflow;
      k = bins - 1;
    }
    ++h.counts[static_cast<std::size_t>(k)];
  }
  return h;
}

std::vector<std::size_t> CountPerBlock(const std::vector<bool>& flags, std::size_t block) {
  SQUINT_ENSURE(block > 0, "block size must be positive");
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < flags.size(); i += block) {
    std::size_t n = 0;
    for (std::size_t j = i; j < std::min(flags.size(), i + block); ++j) n += flags[j] ? 1 : 0;
    out.push_back(n);
  }
  return out;
}

}  // namespace squint::eval
