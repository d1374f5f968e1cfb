// Validation of the corridor options and the cue names shared by CSV columns and YAML keys.
#include "squint/corridor/options.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace squint::corridor {
namespace {

bool Finite(double x) { return std::isfinite(x); }

}  // namespace

const char* CueName(HeadingCue cue) {
  switch (cue) {
    case HeadingCue::kEntropy: return "entropy";
    case HeadingCue::kSymmetry: return "symmetry";
    case HeadingCue::kPhase: return "phase";
    case HeadingCue::kVanishing: return "vanishing";
    case HeadingCue::kBright: return "bright";
  }
  return "?";
}

const char* CueName(DistanceCue cue) {
  switch (cue) {
    case DistanceCue::kTimeToContact: return "ttc";
    case DistanceCue::kJeffrey: return "jeffrey";
    case DistanceCue::kEntropy: return "entropy";
  }
  return "?";
}

const char* ReasonText(Reason reason) {
  switch (reason) {
    case Reason::kNone: return "ok";
    case Reason::kNotProcessed: return "not processed";
    case Reason::kDisabled: return "disabled";
    case Reason::kUniformFrame: return "uniform frame";
    case Reason::kFlatCurve: return "flat curve";
    case Reason::kPeakAtBorder: return "peak at border";
    case Reason::kNoBrightCluster: return "no bright cluster";
    case Reason::kZeroGradient: return "zero gradient";
    case Reason::kNoMatch: return "no self-similar match";
    case Reason::kDegenerateGeometry: return "vanishing point outside the view";
    case Reason::kNoPreviousFrame: return "no previous frame";
    case Reason::kIdenticalFrames: return "identical frames";
    case Reason::kTtcDenominatorZero: return "time-to-contact denominator zero";
    case Reason::kNotApproaching: return "not approaching";
    case Reason::kNoTravel: return "travelled distance unknown";
    case Reason::kOutOfRange: return "out of range";
  }
  return "?";
}

std::string HeadingFilterOptions::Validate() const {
  if (!Finite(process_std_deg_per_sqrt_s) || process_std_deg_per_sqrt_s < 0.0)
    return "heading.filter.process_std_deg_per_sqrt_s must be >= 0";
  if (!Finite(process_std_deg) || process_std_deg < 0.0) return "heading.filter.process_std_deg must be >= 0";
  if (!Finite(odom_noise_fraction) || odom_noise_fraction < 0.0)
    return "heading.filter.odom_noise_fraction must be >= 0";
  if (!Finite(no_odom_std_deg) || no_odom_std_deg < 0.0) return "heading.filter.no_odom_std_deg must be >= 0";
  if (!Finite(gate_chi2) || gate_chi2 <= 0.0) return "heading.filter.gate_chi2 must be > 0";
  if (reinit_after_rejections < 1) return "heading.filter.reinit_after_rejections must be >= 1";
  return {};
}

std::string HeadingOptions::Validate() const {
  std::ostringstream e;
  for (int i = 0; i < kHeadingCueCount; ++i) {
    const auto& c = cues[i];
    const char* name = CueName(static_cast<HeadingCue>(i));
    if (!Finite(c.weight) || c.weight < 0.0) e << "heading.cues." << name << ".weight must be >= 0; ";
    if (!Finite(c.scale) || c.scale == 0.0) e << "heading.cues." << name << ".scale must be finite and non-zero; ";
    if (!Finite(c.bias_deg)) e << "heading.cues." << name << ".bias_deg must be finite; ";
    if (!Finite(c.std_deg) || c.std_deg <= 0.0) e << "heading.cues." << name << ".std_deg must be > 0; ";
  }
  if (slice_width_px < 1 || slice_width_px > 15) e << "heading.slice_width_px must be in [1, 15]; ";
  if (border_px < 0 || border_px > 8) e << "heading.border_px must be in [0, 8]; ";
  if (!Finite(min_prominence) || min_prominence < 0.0 || min_prominence > 1.0)
    e << "heading.min_prominence must be in [0, 1]; ";
  if (column_bits < 1 || column_bits > 4) e << "heading.column_bits must be in [1, 4]; ";
  if (symmetry_min_half_width_px < 1 || symmetry_min_half_width_px > symmetry_half_width_px ||
      symmetry_half_width_px > 15)
    e << "heading.symmetry_min_half_width_px and symmetry_half_width_px need 1 <= min <= max <= 15; ";
  if (vanishing_bits < 1 || vanishing_bits > 4) e << "heading.vanishing_bits must be in [1, 4]; ";
  if (!Finite(vanishing_row_margin_px) || vanishing_row_margin_px < 0.0)
    e << "heading.vanishing_row_margin_px must be >= 0; ";
  if (!Finite(vanishing_max_outside_px) || vanishing_max_outside_px < 0.0)
    e << "heading.vanishing_max_outside_px must be >= 0; ";
  if (!Finite(bright_rows_fraction) || bright_rows_fraction <= 0.0 || bright_rows_fraction > 1.0)
    e << "heading.bright_rows_fraction must be in (0, 1]; ";
  if (!Finite(bright_min_separation) || bright_min_separation < 0.0) e << "heading.bright_min_separation must be >= 0; ";
  if (!Finite(bright_max_fraction) || bright_max_fraction <= 0.0 || bright_max_fraction > 1.0)
    e << "heading.bright_max_fraction must be in (0, 1]; ";
  if (kmeans_iterations < 1 || kmeans_iterations > 100) e << "heading.kmeans_iterations must be in [1, 100]; ";
  if (!Finite(phase_min_gradient) || phase_min_gradient < 0.0) e << "heading.phase_min_gradient must be >= 0; ";
  if (!Finite(phase_max_deg) || phase_max_deg <= 0.0 || phase_max_deg >= 90.0)
    e << "heading.phase_max_deg must be in (0, 90); ";
  if (!Finite(phase_min_vertical_deg) || phase_min_vertical_deg < 0.0 || phase_min_vertical_deg >= 90.0)
    e << "heading.phase_min_vertical_deg must be in [0, 90); ";
  if (!Finite(phase_min_horizon_rows) || phase_min_horizon_rows < 0.0)
    e << "heading.phase_min_horizon_rows must be >= 0; ";
  if (!Finite(max_abs_heading_deg) || max_abs_heading_deg <= 0.0 || max_abs_heading_deg >= 90.0)
    e << "heading.max_abs_heading_deg must be in (0, 90); ";
  if (!Finite(agreement_deg) || agreement_deg <= 0.0) e << "heading.agreement_deg must be > 0; ";
  if (min_consensus_cues < 1 || min_consensus_cues > kHeadingCueCount)
    e << "heading.min_consensus_cues must be in [1, " << kHeadingCueCount << "]; ";
  if (!Finite(fallback_deg_per_column) || fallback_deg_per_column <= 0.0)
    e << "heading.fallback_deg_per_column must be > 0; ";
  if (const std::string f = filter.Validate(); !f.empty()) e << f << "; ";
  std::string s = e.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

double DistanceOptions::FusionWeight(int cue, double dist_m) const {
  const auto c = static_cast<std::size_t>(cue);
  const double g = 1.0 + error_growth_per_m[c] * std::max(0.0, dist_m);
  return weights[c] / (g * g);
}

std::string FloorContactOptions::Validate() const {
  std::ostringstream e;
  if (!Finite(half_width_deg) || half_width_deg <= 0.0 || half_width_deg > 30.0)
    e << "distance.floor_contact.half_width_deg must be in (0, 30]; ";
  if (!Finite(min_step) || min_step <= 0.0) e << "distance.floor_contact.min_step must be positive; ";
  if (!Finite(min_column_fraction) || min_column_fraction <= 0.0 || min_column_fraction > 1.0)
    e << "distance.floor_contact.min_column_fraction must be in (0, 1]; ";
  if (!Finite(min_m) || !Finite(max_m) || min_m < 0.0 || max_m <= min_m)
    e << "distance.floor_contact needs 0 <= min_m < max_m; ";
  if (!Finite(agreement_ratio) || agreement_ratio < 0.0) e << "distance.floor_contact.agreement_ratio must be >= 0; ";
  if (!Finite(motion_window_m) || motion_window_m < 0.0)
    e << "distance.floor_contact.motion_window_m must be >= 0 (0 = off); ";
  if (!Finite(motion_tol_rows) || motion_tol_rows <= 0.0) e << "distance.floor_contact.motion_tol_rows must be positive; ";
  if (!Finite(motion_min_fraction) || motion_min_fraction <= 0.0 || motion_min_fraction > 1.0)
    e << "distance.floor_contact.motion_min_fraction must be in (0, 1]; ";
  if (motion_min_readings < 2 || motion_min_readings > kMaxFloorMotionReadings)
    e << "distance.floor_contact.motion_min_readings must be in [2, " << kMaxFloorMotionReadings << "]; ";
  if (!Finite(lined_wall_rel_step) || lined_wall_rel_step < 0.0 || lined_wall_rel_step > 1.0)
    e << "distance.floor_contact.lined_wall_rel_step must be in [0, 1] (0 = off); ";
  return e.str();
}

std::string DistanceOptions::Validate() const {
  std::ostringstream e;
  for (int i = 0; i < kDistanceCueCount; ++i)
    if (!Finite(weights[i]) || weights[i] < 0.0)
      e << "distance.cues." << CueName(static_cast<DistanceCue>(i)) << ".weight must be >= 0; ";
  if (!Finite(ttc_scale) || ttc_scale == 0.0) e << "distance.ttc_scale must be finite and non-zero; ";
  if (!Finite(ttc_bias_m)) e << "distance.ttc_bias_m must be finite; ";
  if (!Finite(speed_mps) || speed_mps < 0.0) e << "distance.speed_mps must be >= 0; ";
  if (!Finite(alpha2)) e << "distance.alpha2 must be finite; ";
  if (!Finite(beta2)) e << "distance.beta2 must be finite; ";
  if (!Finite(alpha3)) e << "distance.alpha3 must be finite; ";
  if (image_bits < 1 || image_bits > 8) e << "distance.image_bits must be in [1, 8]; ";
  if (!Finite(min_m) || !Finite(max_m) || min_m < 0.0 || max_m <= min_m)
    e << "distance.min_m and max_m need 0 <= min_m < max_m; ";
  for (int i = 0; i < kDistanceCueCount; ++i) {
    const std::string cue = std::string("distance.cues.") + CueName(static_cast<DistanceCue>(i));
    if (!Finite(valid_min_m[i]) || !Finite(valid_max_m[i]) || valid_min_m[i] < 0.0 || valid_max_m[i] <= valid_min_m[i])
      e << cue << " needs 0 <= valid_min_m < valid_max_m; ";
    if (!Finite(error_growth_per_m[i]) || error_growth_per_m[i] < 0.0) e << cue << ".error_growth_per_m must be >= 0; ";
  }
  if (!Finite(fused_max_std_m) || fused_max_std_m < 0.0) e << "distance.fused_max_std_m must be >= 0; ";
  if (const std::string fc = floor_contact.Validate(); !fc.empty()) e << fc;
  if (!Finite(ttc_window_min_height_px) || ttc_window_min_height_px < 1.0)
    e << "distance.ttc_window_min_height_px must be >= 1; ";
  if (median_frames < 1 || median_frames > kMaxDistanceMedianFrames)
    e << "distance.median_frames must be in [1, " << kMaxDistanceMedianFrames << "]; ";
  if (!Finite(ttc_max_scale) || ttc_max_scale <= 1.0 || ttc_max_scale > 4.0)
    e << "distance.ttc_max_scale must be in (1, 4]; ";
  if (!Finite(ttc_window_half_width_m) || ttc_window_half_width_m <= 0.0)
    e << "distance.ttc_window_half_width_m must be positive; ";
  if (!Finite(ttc_window_height_factor) || ttc_window_height_factor <= 0.0)
    e << "distance.ttc_window_height_factor must be positive; ";
  if (!Finite(ttc_window_min_px) || ttc_window_min_px < 1.0 || ttc_window_min_px > kGlanceWidth)
    e << "distance.ttc_window_min_px must be in [1, " << kGlanceWidth << "]; ";
  if (!Finite(ttc_warmup_m) || ttc_warmup_m < 0.0) e << "distance.ttc_warmup_m must be >= 0; ";
  if (!Finite(ttc_initial_baseline_m) || ttc_initial_baseline_m <= 0.0)
    e << "distance.ttc_initial_baseline_m must be positive; ";
  if (!Finite(ttc_min_contrast) || ttc_min_contrast < 0.0) e << "distance.ttc_min_contrast must be >= 0; ";
  if (!Finite(ttc_min_ncc) || ttc_min_ncc < -1.0 || ttc_min_ncc > 1.0) e << "distance.ttc_min_ncc must be in [-1, 1]; ";
  if (!Finite(ttc_cell_px) || (ttc_cell_px != 0.0 && ttc_cell_px < 3.0))
    e << "distance.ttc_cell_px must be 0 (off) or >= 3; ";
  if (!Finite(ttc_cell_quantile) || ttc_cell_quantile < 0.0 || ttc_cell_quantile > 1.0)
    e << "distance.ttc_cell_quantile must be in [0, 1]; ";
  if (ttc_cell_min_count < 1) e << "distance.ttc_cell_min_count must be >= 1; ";
  if (!(ttc_cell_max_se_fraction > 0.0)) e << "distance.ttc_cell_max_se_fraction must be positive; ";
  if (ttc_cell_nearest < 0 || ttc_cell_nearest > 96) e << "distance.ttc_cell_nearest must be in [0, 96]; ";
  if (!Finite(ttc_cell_min_expansion) || ttc_cell_min_expansion < 0.0)
    e << "distance.ttc_cell_min_expansion must be >= 0; ";
  if (!Finite(ttc_glance_scale) || ttc_glance_scale < 1.0 || ttc_glance_scale > 4.0)
    e << "distance.ttc_glance_scale must be in [1, 4]; ";
  else if (ttc_glance_scale != 1.0 && !ttc_scale_search)
    e << "distance.ttc_glance_scale other than 1 needs ttc_scale_search; ";
  if (ttc_max_baseline_frames < 1 || ttc_max_baseline_frames > kMaxTtcBaselineFrames)
    e << "distance.ttc_max_baseline_frames must be in [1, " << kMaxTtcBaselineFrames << "]; ";
  if (!Finite(ttc_baseline_fraction) || ttc_baseline_fraction <= 0.0 || ttc_baseline_fraction > 1.0)
    e << "distance.ttc_baseline_fraction must be in (0, 1]; ";
  std::string s = e.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

std::string GateOptions::Validate() const {
  if (!Finite(threshold) || threshold < 0.0) return "gate.threshold must be >= 0";
  if (max_skipped_frames < 0) return "gate.max_skipped_frames must be >= 0";
  return {};
}

std::string CorridorOptions::Validate() const {
  std::string s;
  for (const std::string& part : {heading.Validate(), distance.Validate(), gate.Validate()}) {
    if (part.empty()) continue;
    if (!s.empty()) s += "; ";
    s += part;
  }
  return s;
}

}  // namespace squint::corridor
