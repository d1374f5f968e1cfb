// Calibration maths for the corridor measures: trimmed least squares and per-measure fits
// (paper §5.1–5.2). See calibration.hpp for the models.
#include "squint/corridor/calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

#include "squint/core/error.hpp"
#include "squint/core/median.hpp"

namespace squint::corridor {
namespace {

double Median(std::vector<double> v) { return MedianInPlace(v); }

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Theil–Sen estimate over the kept samples (a deterministic stride keeps it to ~4·10^6 pairs);
// none when no pair has distinct x.
std::optional<std::pair<double, double>> TheilSen(std::span<const double> x, std::span<const double> y,
                                                  const std::vector<bool>& keep, bool with_intercept) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (keep[i]) idx.push_back(i);
  const std::size_t stride = std::max<std::size_t>(1, idx.size() / 2000);
  std::vector<std::size_t> sub;
  for (std::size_t k = 0; k < idx.size(); k += stride) sub.push_back(idx[k]);
  std::vector<double> slopes;
  if (with_intercept) {
    for (std::size_t a = 0; a < sub.size(); ++a)
      for (std::size_t b = a + 1; b < sub.size(); ++b) {
        const double dx = x[sub[b]] - x[sub[a]];
        if (dx != 0.0) slopes.push_back((y[sub[b]] - y[sub[a]]) / dx);
      }
  } else {
    for (std::size_t i : sub)
      if (x[i] != 0.0) slopes.push_back(y[i] / x[i]);
  }
  if (slopes.empty()) return std::nullopt;
  const double slope = Median(std::move(slopes));
  double intercept = 0.0;
  if (with_intercept) {
    std::vector<double> r;
    for (std::size_t i : idx) r.push_back(y[i] - slope * x[i]);
    intercept = Median(std::move(r));
  }
  return std::make_pair(slope, intercept);
}

// Shared robust least squares: design columns are x (and 1 when with_intercept).
LineFit FitImpl(std::span<const double> x, std::span<const double> y, const std::string& what,
                const LineFitOptions& options, bool with_intercept) {
  SQUINT_ENSURE(x.size() == y.size(), "x and y must have equal sizes");
  if (const std::string bad = options.Validate(); !bad.empty()) throw Error(what + ": " + bad);
  const std::size_t n = x.size();
  LineFit fit;
  fit.samples = n;
  std::vector<bool> keep(n, true);
  for (std::size_t i = 0; i < n; ++i) keep[i] = std::isfinite(x[i]) && std::isfinite(y[i]);

  // A robust start (Theil–Sen: the median of pairwise slopes) so that the trimming is judged
  // against a fit that gross outliers have not already pulled.
  std::optional<std::pair<double, double>> start;
  if (options.trim_iterations > 0) start = TheilSen(x, y, keep, with_intercept);
  if (start) {
    std::vector<double> abs_res;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) abs_res.push_back(std::abs(y[i] - start->first * x[i] - start->second));
    const double sigma = 1.4826 * Median(abs_res);
    if (sigma > 0.0)
      for (std::size_t i = 0; i < n; ++i)
        if (keep[i]) keep[i] = std::abs(y[i] - start->first * x[i] - start->second) <= options.trim_sigma * sigma;
  }

  for (int iter = 0;; ++iter) {
    std::size_t m = 0;
    double mean_x = 0.0, mean_x2 = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) {
        ++m;
        mean_x += x[i];
        mean_x2 += x[i] * x[i];
      }
    if (m < options.min_samples)
      throw Error(what + ": singular fit: only " + std::to_string(m) + " usable samples (need at least " +
                  std::to_string(options.min_samples) + ")");
    mean_x /= static_cast<double>(m);
    mean_x2 /= static_cast<double>(m);
    const double spread = with_intercept ? std::sqrt(std::max(0.0, mean_x2 - mean_x * mean_x))
                                         : std::sqrt(mean_x2);
    if (!(spread > options.min_x_spread))
      throw Error(what + ": singular fit: the " + std::string(with_intercept ? "values" : "magnitudes") +
                  " of the fitted variable do not vary (spread " + Num(spread) + " over " +
                  std::to_string(m) + " samples)");
    Eigen::MatrixXd a(static_cast<Eigen::Index>(m), with_intercept ? 2 : 1);
    Eigen::VectorXd b(static_cast<Eigen::Index>(m));
    Eigen::Index r = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) {
        a(r, 0) = x[i];
        if (with_intercept) a(r, 1) = 1.0;
        b(r) = y[i];
        ++r;
      }
    const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
    fit.slope = sol(0);
    fit.intercept = with_intercept ? sol(1) : 0.0;
    fit.inliers = m;
    const Eigen::VectorXd res = b - a * sol;
    fit.residual_rms = std::sqrt(res.squaredNorm() / static_cast<double>(m));
    if (iter >= options.trim_iterations) break;
    // Robust σ of all finite samples' residuals against the current fit.
    std::vector<double> abs_res;
    for (std::size_t i = 0; i < n; ++i)
      if (std::isfinite(x[i]) && std::isfinite(y[i]))
        abs_res.push_back(std::abs(y[i] - fit.slope * x[i] - fit.intercept));
    const double sigma = 1.4826 * Median(abs_res);
    if (!(sigma > 0.0)) break;  // exact fit on more than half the samples: nothing to trim
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
      const bool k = std::abs(y[i] - fit.slope * x[i] - fit.intercept) <= options.trim_sigma * sigma;
      changed = changed || (k != keep[i]);
      keep[i] = k;
    }
    if (!changed) break;
  }
  return fit;
}

// The offset b of truth ≈ raw + b: the median of truth - raw, then the mean of the samples
// within trim_sigma robust σ of it, repeated trim_iterations times. Throws when the readings do
// not vary (a cue that carries no heading) or too few samples remain.
double FitOffset(std::span<const double> raw, std::span<const double> truth, const std::string& what,
                 const LineFitOptions& options, double& inlier_fraction) {
  if (const std::string bad = options.Validate(); !bad.empty()) throw Error(what + ": " + bad);
  std::vector<double> d;
  double mean = 0.0, mean2 = 0.0;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!std::isfinite(raw[i]) || !std::isfinite(truth[i])) continue;
    d.push_back(truth[i] - raw[i]);
    mean += raw[i];
    mean2 += raw[i] * raw[i];
  }
  if (d.size() < options.min_samples)
    throw Error(what + ": singular fit: only " + std::to_string(d.size()) + " usable samples (need at least " +
                std::to_string(options.min_samples) + ")");
  const double n = static_cast<double>(d.size());
  const double spread = std::sqrt(std::max(0.0, mean2 / n - (mean / n) * (mean / n)));
  if (!(spread > options.min_x_spread))
    throw Error(what + ": singular fit: the readings do not vary (spread " + Num(spread) + " over " +
                std::to_string(d.size()) + " samples)");
  double offset = Median(d);
  std::size_t kept = d.size();
  for (int iter = 0; iter < options.trim_iterations; ++iter) {
    std::vector<double> abs_res;
    abs_res.reserve(d.size());
    for (double v : d) abs_res.push_back(std::abs(v - offset));
    const double sigma = 1.4826 * Median(abs_res);
    if (!(sigma > 0.0)) {  // more than half the samples agree exactly: they are the inliers
      kept = static_cast<std::size_t>(std::count(abs_res.begin(), abs_res.end(), 0.0));
      break;
    }
    double sum = 0.0;
    std::size_t m = 0;
    for (double v : d)
      if (std::abs(v - offset) <= options.trim_sigma * sigma) sum += v, ++m;
    if (m < options.min_samples) break;
    const double next = sum / static_cast<double>(m);
    kept = m;
    if (next == offset) break;
    offset = next;
  }
  inlier_fraction = static_cast<double>(kept) / static_cast<double>(d.size());
  return offset;
}

void RequireFinite(double v, const std::string& what) {
  if (!std::isfinite(v)) throw Error(what + ": the fit produced a non-finite value");
}

}  // namespace

std::string LineFitOptions::Validate() const {
  if (trim_iterations < 0) return "trim_iterations must be >= 0";
  if (!(trim_sigma > 0.0)) return "trim_sigma must be positive";
  if (min_samples < 2) return "min_samples must be >= 2";
  if (!(min_x_spread >= 0.0)) return "min_x_spread must be >= 0";
  return {};
}

std::string HeadingFitOptions::Validate() const {
  if (std::string s = line.Validate(); !s.empty()) return s;
  if (!(bin_width_deg > 0.0)) return "bin_width_deg must be positive";
  if (!(reliable_max_rmse_deg > 0.0)) return "reliable_max_rmse_deg must be positive";
  return {};
}

std::string DistanceFitOptions::Validate() const {
  if (std::string s = line.Validate(); !s.empty()) return s;
  if (!(min_truth_m >= 0.0) || !(max_truth_m > min_truth_m)) return "need 0 <= min_truth_m < max_truth_m";
  return {};
}

LineFit FitLine(std::span<const double> x, std::span<const double> y, const std::string& what,
                const LineFitOptions& options) {
  return FitImpl(x, y, what, options, true);
}

LineFit FitProportional(std::span<const double> x, std::span<const double> y, const std::string& what,
                        const LineFitOptions& options) {
  return FitImpl(x, y, what, options, false);
}

HeadingFit FitHeading(std::span<const HeadingSample> samples, const std::string& what,
                      const HeadingFitOptions& options) {
  if (const std::string bad = options.Validate(); !bad.empty()) throw Error(what + ": " + bad);
  std::vector<double> raw, truth;
  raw.reserve(samples.size());
  truth.reserve(samples.size());
  double truth_min = HUGE_VAL, truth_max = -HUGE_VAL;
  for (const HeadingSample& s : samples) {
    raw.push_back(s.raw);
    truth.push_back(s.truth_deg);
    truth_min = std::min(truth_min, s.truth_deg);
    truth_max = std::max(truth_max, s.truth_deg);
  }
  // All true headings equal: scale and bias cannot be told apart from the measure's own spread.
  if (!samples.empty() && truth_max - truth_min < options.bin_width_deg)
    throw Error(what + ": singular fit: every sample has the same true heading (" + Num(truth_min) +
                " deg); calibration needs sequences that sweep the heading");
  HeadingFit fit;
  if (options.fit_scale) {
    // reading = a · truth + b, so calibrated = (reading - b) / a.
    const LineFit line = FitLine(truth, raw, what, options.line);
    if (!(line.slope > 0.0))
      throw Error(what + ": the readings do not grow with the true heading (slope " + Num(line.slope) +
                  "); the cue cannot be calibrated");
    fit.scale = 1.0 / line.slope;
    fit.bias_deg = -line.intercept / line.slope;
    fit.inlier_fraction = static_cast<double>(line.inliers) / static_cast<double>(line.samples);
  } else {
    fit.scale = 1.0;
    fit.bias_deg = FitOffset(raw, truth, what, options.line, fit.inlier_fraction);
  }
  RequireFinite(fit.scale, what);
  RequireFinite(fit.bias_deg, what);
  fit.samples = samples.size();

  double sum = 0.0, sum2 = 0.0;
  std::map<long long, std::pair<std::size_t, double>> bins;  // bin -> (count, Σ err²)
  for (const HeadingSample& s : samples) {
    const double e = fit.scale * s.raw + fit.bias_deg - s.truth_deg;
    sum += e;
    sum2 += e * e;
    auto& b = bins[static_cast<long long>(std::floor(s.truth_deg / options.bin_width_deg + 0.5))];
    ++b.first;
    b.second += e * e;
  }
  const double n = static_cast<double>(samples.size());
  fit.rmse_deg = std::sqrt(sum2 / n);
  fit.error_std_deg = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));

  // Reliable range: walk outward from the bin centred on 0 while bins pass; sparse bins neither
  // pass nor fail.
  auto passes = [&](long long k) -> std::optional<bool> {
    const auto it = bins.find(k);
    if (it == bins.end() || it->second.first < options.reliable_min_bin_samples) return std::nullopt;
    return std::sqrt(it->second.second / static_cast<double>(it->second.first)) <= options.reliable_max_rmse_deg;
  };
  const long long k_min = bins.begin()->first, k_max = bins.rbegin()->first;
  if (passes(0).value_or(true)) {
    long long hi = 0, lo = 0;
    for (long long k = 1; k <= k_max; ++k) {
      const auto p = passes(k);
      if (p && !*p) break;
      hi = k;
    }
    for (long long k = -1; k >= k_min; --k) {
      const auto p = passes(k);
      if (p && !*p) break;
      lo = k;
    }
    fit.reliable_min_deg = (static_cast<double>(lo) - 0.5) * options.bin_width_deg;
    fit.reliable_max_deg = (static_cast<double>(hi) + 0.5) * options.bin_width_deg;
  } else {
    fit.reliable_min_deg = 1.0;
    fit.reliable_max_deg = -1.0;
  }
  return fit;
}

double DistanceSpread::Sigma(double estimate_m) const {
  return sigma0_m + sigma_slope * std::max(0.0, estimate_m);
}

DistanceSpread FitDistanceSpread(std::span<const double> estimates_m, std::span<const double> errors_m,
                                 double floor_m) {
  SQUINT_ENSURE(estimates_m.size() == errors_m.size(), "equal sizes");
  // E|e| = σ·sqrt(2/π) for a normal error, so σ ≈ |e|·sqrt(π/2).
  const double k = std::sqrt(std::numbers::pi / 2.0);
  std::vector<double> x, y;
  for (std::size_t i = 0; i < estimates_m.size(); ++i) {
    if (!std::isfinite(estimates_m[i]) || !std::isfinite(errors_m[i])) continue;
    x.push_back(std::max(0.0, estimates_m[i]));
    y.push_back(std::abs(errors_m[i]) * k);
  }
  DistanceSpread s;
  if (x.empty()) return s;
  // Robust (Theil–Sen start, 3σ trimming): a few wild estimates far beyond the range (a cue
  // matching nothing on a plain wall) would otherwise tilt the line to σ ≈ d̂ for every cue.
  LineFitOptions plain;
  plain.min_samples = 2;
  try {
    const LineFit f = FitLine(x, y, "spread", plain);
    s.sigma0_m = f.intercept;
    s.sigma_slope = f.slope;
  } catch (const Error&) {
    s.sigma_slope = 0.0;
    double sum = 0.0;
    for (double v : y) sum += v;
    s.sigma0_m = sum / static_cast<double>(y.size());
  }
  if (s.sigma_slope < 0.0) {  // error shrinking with distance is not a model we trust: constant σ
    double sum = 0.0;
    for (double v : y) sum += v;
    s.sigma_slope = 0.0;
    s.sigma0_m = sum / static_cast<double>(y.size());
  }
  s.sigma0_m = std::max(s.sigma0_m, floor_m);
  return s;
}

namespace {

// Keeps samples in the truth window; fills x = raw, t = truth.
void Select(std::span<const DistanceSample> samples, const DistanceFitOptions& options, std::vector<double>& raw,
            std::vector<double>& truth) {
  for (const DistanceSample& s : samples) {
    if (s.truth_m < options.min_truth_m || s.truth_m > options.max_truth_m) continue;
    if (!std::isfinite(s.raw)) continue;
    raw.push_back(s.raw);
    truth.push_back(s.truth_m);
  }
}

void CheckDistanceSpread(const std::vector<double>& truth, const std::string& what) {
  if (truth.empty()) throw Error(what + ": singular fit: no samples within the distance window");
  const auto [lo, hi] = std::minmax_element(truth.begin(), truth.end());
  if (*hi - *lo < 0.5)
    throw Error(what + ": singular fit: every sample is at (nearly) one distance to the end (" + Num(*lo) + " to " +
                Num(*hi) + " m); calibration needs sequences that approach the end");
}

void FinishDistance(DistanceFit& fit, const std::vector<double>& est, const std::vector<double>& truth,
                    std::size_t inliers) {
  std::vector<double> err(est.size());
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    err[i] = est[i] - truth[i];
    sum += err[i];
    sum2 += err[i] * err[i];
  }
  const double n = static_cast<double>(est.size());
  fit.samples = est.size();
  fit.rmse_m = std::sqrt(sum2 / n);
  fit.error_std_m = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  fit.inlier_fraction = static_cast<double>(inliers) / n;
  // The spread is fitted on the robust inliers' scale: errors beyond 3 robust σ are what the
  // validity checks and the filter's gate exist to catch.
  fit.spread = FitDistanceSpread(est, err);
}

}  // namespace

DistanceFit FitTtcScale(std::span<const DistanceSample> samples, const std::string& what,
                        const DistanceFitOptions& options) {
  std::vector<double> raw, truth;
  Select(samples, options, raw, truth);
  CheckDistanceSpread(truth, what);
  // truth ≈ scale · raw (the paper's TTC scale check). Regressing the reading on the truth and
  // inverting (as for heading) was tried: on ../shared/data/drive-* the distance readings are
  // not linear in the truth with small noise, and the inverted fits came out worse on the test
  // split (fused 1.9 m instead of 1.4 m within 5 m; Jeffrey's line flat, so α2 exploded). A
  // fitted intercept was tried too: the far readings' outliers then flatten the line to a
  // near-constant, so the model keeps the physical zero.
  const LineFit line = FitProportional(raw, truth, what, options.line);
  DistanceFit fit;
  fit.checked_scale = line.slope;
  fit.beta = 0.0;
  RequireFinite(fit.checked_scale, what);
  if (!(fit.checked_scale > 0.0))
    throw Error(what + ": the time-to-contact scale came out " + Num(fit.checked_scale) +
                " (must be positive): the estimates do not grow with the distance");
  fit.scale = options.ttc_fit_scale ? fit.checked_scale : 1.0;
  std::vector<double> est(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) est[i] = fit.scale * raw[i] + fit.beta;
  FinishDistance(fit, est, truth, line.inliers);
  return fit;
}

DistanceFit FitJeffrey(std::span<const DistanceSample> samples, const std::string& what,
                       const DistanceFitOptions& options) {
  std::vector<double> raw, truth;
  Select(samples, options, raw, truth);
  CheckDistanceSpread(truth, what);
  const LineFit line = FitLine(raw, truth, what, options.line);
  DistanceFit fit;
  fit.alpha = -line.slope;
  fit.beta = line.intercept;
  RequireFinite(fit.alpha, what);
  RequireFinite(fit.beta, what);
  std::vector<double> est(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) est[i] = fit.beta - fit.alpha * raw[i];
  FinishDistance(fit, est, truth, line.inliers);
  return fit;
}

DistanceFit FitEntropyDistance(std::span<const DistanceSample> samples, const std::string& what,
                               const DistanceFitOptions& options) {
  std::vector<double> raw, truth;
  Select(samples, options, raw, truth);
  CheckDistanceSpread(truth, what);
  std::vector<double> inv_truth(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) inv_truth[i] = 1.0 / truth[i];
  const LineFit line = FitProportional(inv_truth, raw, what, options.line);
  DistanceFit fit;
  fit.alpha = line.slope;
  RequireFinite(fit.alpha, what);
  if (fit.alpha == 0.0) throw Error(what + ": singular fit: the entropy difference does not vary with distance");
  // Evaluate in the paper's form d = α3 / ΔH, on samples where ΔH has the fitted sign.
  std::vector<double> est, t;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] == 0.0) continue;
    const double d = fit.alpha / raw[i];
    if (d <= 0.0) continue;
    est.push_back(d);
    t.push_back(truth[i]);
  }
  if (est.empty()) throw Error(what + ": no sample gives a positive distance after the fit");
  FinishDistance(fit, est, t, std::min(line.inliers, est.size()));
  return fit;
}

}  // namespace squint::corridor
