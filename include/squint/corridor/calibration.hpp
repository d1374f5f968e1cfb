// Calibration maths for the corridor measures (paper §5.1–5.2): robust linear least squares
// fits of each heading measure's scale and bias, of the distance measures' constants (α2/β2,
// α3, the time-to-contact scale), error spreads for fusion weights and the heading range over
// which a measure is reliable. Pure maths on samples; reading sequences is the caller's job.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace squint::corridor {

// y ≈ slope · x + intercept, fitted by least squares on the inliers.
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  double residual_rms = 0.0;  // of y - fit over the inliers
  std::size_t samples = 0;    // all samples offered
  std::size_t inliers = 0;    // samples kept by the trimming
};

struct LineFitOptions {
  // Iterations of "fit, drop samples whose residual exceeds trim_sigma · σ, refit", where σ is
  // 1.4826 · the median absolute residual (a robust standard deviation). 0 = plain least squares.
  int trim_iterations = 3;
  double trim_sigma = 3.0;
  // Fewer samples than this (after trimming) make the fit singular.
  std::size_t min_samples = 5;
  // The spread of x (population σ) must exceed this, or the fit is singular (one distance
  // only, all headings equal). In x's units.
  double min_x_spread = 1e-6;

  std::string Validate() const;  // empty when valid
};

// Fits y ≈ slope · x + intercept. Throws squint::Error("<what>: ...") when the fit is singular:
// too few samples, or x (nearly) constant. x and y must have equal sizes (SQUINT_ENSURE).
LineFit FitLine(std::span<const double> x, std::span<const double> y, const std::string& what,
                const LineFitOptions& options = {});
// Fits y ≈ slope · x (no intercept). Singular when too few samples or x all (nearly) zero.
LineFit FitProportional(std::span<const double> x, std::span<const double> y, const std::string& what,
                        const LineFitOptions& options = {});

// ---- Heading measures --------------------------------------------------------------------

// One frame of one heading measure: the truth and the measure's uncalibrated answer (a heading
// through the camera model in degrees, or, where no intrinsics are known, the column offset
// from the image centre in glance pixels).
struct HeadingSample {
  double truth_deg = 0.0;
  double raw = 0.0;
};

struct HeadingFitOptions {
  LineFitOptions line;
  // false (default): the readings are camera-model degrees (column -> atan((u - cx) / fx)), so
  // the scale is physics, fixed at 1, and only the bias (mount yaw, a cue's offset) is fitted:
  // the trimmed mean of truth - reading. A free scale fitted on frames where a cue is grossly
  // wrong shrinks towards 0 and would flatten every good reading. true: also fit the scale, by
  // regressing the reading on the truth (the noise is in the reading, not in the ground truth),
  // for readings without a camera model (fallback degrees per column).
  bool fit_scale = false;
  // Width of the true-heading bins over which the reliable range is judged (paper: 1°).
  double bin_width_deg = 1.0;
  // A bin is reliable when the calibrated RMSE over it is at most this ...
  double reliable_max_rmse_deg = 8.0;
  // ... and it holds at least this many samples (sparser bins do not break the range).
  std::size_t reliable_min_bin_samples = 3;

  std::string Validate() const;
};

struct HeadingFit {
  // Calibrated heading = scale · raw + bias_deg (raw in degrees: scale ≈ 1 for a well-modelled
  // camera; raw in pixels: scale is the paper's α in degrees per glance pixel).
  double scale = 1.0;
  double bias_deg = 0.0;
  double error_std_deg = 0.0;   // σ of (calibrated - truth) over ALL samples (fusion weight 1/σ²)
  double rmse_deg = 0.0;        // over all samples
  double inlier_fraction = 0.0;  // of the robust fit
  // The contiguous range of true heading around 0 whose 1° bins all have RMSE within the
  // threshold; empty (min > max) when even the bin at 0 fails.
  double reliable_min_deg = 0.0;
  double reliable_max_deg = 0.0;
  std::size_t samples = 0;
};

// Fits truth ≈ scale · raw + bias (scale fixed at 1 unless options.fit_scale; see there).
// Throws squint::Error("<what>: ...") when singular.
HeadingFit FitHeading(std::span<const HeadingSample> samples, const std::string& what,
                      const HeadingFitOptions& options = {});

// ---- Distance-to-end measures (§4.2, §5.2) ------------------------------------------------

// One frame of the distance measures' raw values beside the true distance to the end.
struct DistanceSample {
  double truth_m = 0.0;
  double raw = 0.0;  // ttc: (s/f)·τ in metres; jeffrey: J; entropy: ΔH = H(I1) - H(I2)
};

struct DistanceFitOptions {
  LineFitOptions line;
  // Samples whose true distance lies outside [min_truth_m, max_truth_m] are not used.
  double min_truth_m = 0.25;
  double max_truth_m = 30.0;
  // Time to contact: apply the fitted scale (true) or only report it as the check and keep the
  // physical scale 1 (false, the default). The scale search's d = s / (σ − 1) has no free
  // constant, and on ../shared/data/drive-* the fitted scale did not carry over from the
  // calibration corridor to the test corridors (fitted 0.79 or 1.29 depending on small changes
  // of the search; test split within 5 m: 1.09 m calibrated against 0.71 m at scale 1).
  bool ttc_fit_scale = false;
  std::string Validate() const;
};

// The error spread of a distance measure as a function of its own estimate:
// σ(d̂) = sigma0_m + sigma_slope · d̂ (fitted to |error| · sqrt(π/2), floored at sigma_floor).
struct DistanceSpread {
  double sigma0_m = 1.0;
  double sigma_slope = 0.0;
  double Sigma(double estimate_m) const;
};

struct DistanceFit {
  // ttc: truth ≈ scale · raw (the TTC scale check: 1 means (s/f)·τ is right as it stands;
  //   beta stays 0).
  // jeffrey: truth ≈ beta - alpha · J  (paper's β2, α2).
  // entropy: truth ≈ alpha / ΔH (paper's α3; fitted as ΔH ≈ α3 · (1/truth), the same model
  //   with errors taken in ΔH, which stays well-conditioned where ΔH crosses 0).
  double scale = 1.0;         // applied (1 unless DistanceFitOptions::ttc_fit_scale)
  double checked_scale = 1.0; // ttc: the fitted scale, applied or not
  double alpha = 0.0;
  double beta = 0.0;
  double rmse_m = 0.0;  // of the calibrated estimate over the used samples
  double error_std_m = 0.0;
  DistanceSpread spread;
  double inlier_fraction = 0.0;
  std::size_t samples = 0;
};

// Throw squint::Error("<what>: ...") when singular (e.g. every sample at one distance).
DistanceFit FitTtcScale(std::span<const DistanceSample> samples, const std::string& what,
                        const DistanceFitOptions& options = {});
DistanceFit FitJeffrey(std::span<const DistanceSample> samples, const std::string& what,
                       const DistanceFitOptions& options = {});
DistanceFit FitEntropyDistance(std::span<const DistanceSample> samples, const std::string& what,
                               const DistanceFitOptions& options = {});

// Fits the spread model to (estimate, error) pairs; falls back to a constant σ when the slope
// is not identifiable. Never negative: sigma0_m ≥ floor_m, sigma_slope ≥ 0.
DistanceSpread FitDistanceSpread(std::span<const double> estimates_m, std::span<const double> errors_m,
                                 double floor_m = 0.05);

}  // namespace squint::corridor
