// Visual sonar: per-column floor-boundary rows of a small grey frame, turned into range per
// bearing through the camera model's floor back-projection.
#include "squint/explore/visual_sonar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "squint/core/error.hpp"

namespace squint::explore {

std::string VisualSonarOptions::Validate() const {
  if (step_window_rows < 1 || step_window_rows > 8) return "step_window_rows must be in [1, 8]";
  if (!(step_threshold > 0.0) || !std::isfinite(step_threshold)) return "step_threshold must be positive";
  if (min_floor_rows < 1 || min_floor_rows > 8) return "min_floor_rows must be in [1, 8]";
  if (median_half_width < 0 || median_half_width > 8) return "median_half_width must be in [0, 8]";
  if (column_half_width < 0 || column_half_width > 4) return "column_half_width must be in [0, 4]";
  if (median_near_bias < 0 || median_near_bias > 8) return "median_near_bias must be in [0, 8]";
  if (!(median_near_range_m >= 0.0) || !std::isfinite(median_near_range_m)) return "median_near_range_m must be >= 0";
  if (!(floor_memory >= 0.0 && floor_memory < 1.0)) return "floor_memory must be in [0, 1)";
  if (!(floor_sigma_factor >= 0.0) || !std::isfinite(floor_sigma_factor)) return "floor_sigma_factor must be >= 0";
  if (!(max_range_m > 0.0) || !std::isfinite(max_range_m)) return "max_range_m must be positive";
  if (!(floor_edge_max_ratio >= 0.0) || !std::isfinite(floor_edge_max_ratio)) return "floor_edge_max_ratio must be >= 0";
  if (floor_edge_max_ratio > 0.0 && !(floor_edge_min_ratio > 1.0 && floor_edge_min_ratio <= floor_edge_max_ratio))
    return "floor_edge_min_ratio must be in (1, floor_edge_max_ratio]";
  if (!(floor_edge_min_range_m >= 0.0) || !std::isfinite(floor_edge_min_range_m)) return "floor_edge_min_range_m must be >= 0";
  if (floor_edge_min_rows < 1 || floor_edge_min_rows > 16) return "floor_edge_min_rows must be in [1, 16]";
  if (min_reference_columns < 1 || min_reference_columns > 640) return "min_reference_columns must be in [1, 640]";
  if (!(gradient_unknown_levels >= 0.0) || !std::isfinite(gradient_unknown_levels)) return "gradient_unknown_levels must be >= 0";
  if (!(far_floor_max_diff >= 0.0) || !std::isfinite(far_floor_max_diff)) return "far_floor_max_diff must be >= 0";
  if (!(far_floor_from_m >= 0.0) || !std::isfinite(far_floor_from_m)) return "far_floor_from_m must be >= 0";
  if (wall_line_band_columns < 2 || wall_line_band_columns > 640) return "wall_line_band_columns must be in [2, 640]";
  if (wall_line_detrend_rows < 1 || wall_line_detrend_rows > 16) return "wall_line_detrend_rows must be in [1, 16]";
  if (!(wall_line_min_std >= 0.0) || !std::isfinite(wall_line_min_std)) return "wall_line_min_std must be >= 0";
  if (!(wall_line_min_correlation > 0.0 && wall_line_min_correlation <= 1.0)) return "wall_line_min_correlation must be in (0, 1]";
  if (wall_line_min_lag < 1 || wall_line_max_lag < wall_line_min_lag || wall_line_max_lag > 64)
    return "wall_line lags must satisfy 1 <= wall_line_min_lag <= wall_line_max_lag <= 64";
  return {};
}

VisualSonar::VisualSonar(const CameraModel& camera, const VisualSonarOptions& options)
    : camera_(camera), options_(options) {
  if (std::string e = camera_.Validate(); !e.empty()) throw Error("visual sonar: camera: " + e);
  if (std::string e = options_.Validate(); !e.empty()) throw Error("visual sonar: " + e);
  const int w = camera_.width;
  const int h = camera_.height;
  const double horizon = camera_.HorizonRow();
  if (!(horizon > 0.0 && horizon < h - 2)) throw Error("visual sonar: the horizon is not inside the frame (check the camera pitch)");
  top_row_ = std::max(0, static_cast<int>(std::floor(horizon)) - 1);
  range_.assign(static_cast<std::size_t>(w * h), std::numeric_limits<double>::infinity());
  bearing_.assign(static_cast<std::size_t>(w), 0.0);
  for (int u = 0; u < w; ++u) {
    bearing_[static_cast<std::size_t>(u)] = camera_.BearingOfColumn(u);
    for (int v = 0; v < h; ++v) {
      // The boundary between rows v and v + 1 (the last row's lower edge for v = h - 1).
      const double row = std::min(v + 0.5, h - 0.5);
      if (const auto fp = camera_.FloorPoint({static_cast<double>(u), row}))
        range_[static_cast<std::size_t>(v * w + u)] = fp->norm();
    }
  }
  near_blind_m_ = range_[static_cast<std::size_t>((h - 1) * w + w / 2)];
  profile_.assign(static_cast<std::size_t>(h), 0.0f);
  out_.assign(static_cast<std::size_t>(w), SonarColumn{});
  raw_.assign(static_cast<std::size_t>(w), 0.0);
  rows_.assign(static_cast<std::size_t>(w), -1);
  window_.assign(static_cast<std::size_t>(2 * options_.median_half_width + 1), 0.0);
  bottom_.assign(static_cast<std::size_t>(w), 0.0f);
  top_.assign(static_cast<std::size_t>(w), 0.0f);
  ref_window_.assign(static_cast<std::size_t>(w), 0.0f);
  unknown_.assign(static_cast<std::size_t>(w), 0);
  edge_.assign(static_cast<std::size_t>(w), 0.0);
  reference_floor_rows_ = options_.min_floor_rows + 3;
  band_rows_.assign(static_cast<std::size_t>(h), 0.0);
  line_.assign(static_cast<std::size_t>(h), 0.0);
  horizon_profile_.assign(static_cast<std::size_t>(w), 0.0f);
}

void VisualSonar::MeasureWallLines(GrayView image) {
  const int w = camera_.width;
  const int h = camera_.height;
  const int bw = options_.wall_line_band_columns;
  const int r = options_.wall_line_detrend_rows;
  const int n = h - 2 * r;  // rows with a full detrend window
  wall_line_fraction_ = 0.0;
  if (n <= options_.wall_line_min_lag + 2) return;  // too few rows for a period: no band is lined
  int bands = 0, lined = 0;
  for (int u0 = 0; u0 + bw <= w; u0 += bw) {
    ++bands;
    for (int v = 0; v < h; ++v) {
      const std::uint8_t* row = image.Row(v);
      int s = 0;
      for (int x = u0; x < u0 + bw; ++x) s += row[x];
      band_rows_[static_cast<std::size_t>(v)] = static_cast<double>(s) / bw;
    }
    double mean = 0.0;
    for (int i = 0; i < n; ++i) {
      const int v = i + r;
      double s = 0.0;
      for (int j = v - r; j <= v + r; ++j) s += band_rows_[static_cast<std::size_t>(j)];
      line_[static_cast<std::size_t>(i)] = band_rows_[static_cast<std::size_t>(v)] - s / (2 * r + 1);
      mean += line_[static_cast<std::size_t>(i)];
    }
    mean /= n;
    double e = 0.0;
    for (int i = 0; i < n; ++i) {
      line_[static_cast<std::size_t>(i)] -= mean;
      e += line_[static_cast<std::size_t>(i)] * line_[static_cast<std::size_t>(i)];
    }
    e /= n;
    if (!(e > 0.0) || std::sqrt(e) < options_.wall_line_min_std) continue;
    double best = 0.0;
    for (int lag = options_.wall_line_min_lag; lag <= std::min(options_.wall_line_max_lag, n - 3); ++lag) {
      double c = 0.0;
      for (int i = 0; i + lag < n; ++i) c += line_[static_cast<std::size_t>(i)] * line_[static_cast<std::size_t>(i + lag)];
      best = std::max(best, c / (n - lag) / e);
    }
    if (best >= options_.wall_line_min_correlation) ++lined;
  }
  wall_line_fraction_ = bands > 0 ? static_cast<double>(lined) / bands : 0.0;
}

int VisualSonar::FindStep(int base) const {
  // Scans up from row `base` (the region's lowest row) for the lowest row that starts something
  // else: see Process. Returns -1 when none below top_row_.
  const int k = options_.step_window_rows;
  const float thr = static_cast<float>(options_.step_threshold);
  const float a = static_cast<float>(options_.floor_memory);
  const float sig = static_cast<float>(options_.floor_sigma_factor);
  float fmean = profile_[static_cast<std::size_t>(base)];
  float fvar = 0.0f;
  auto step_at = [&](int v) {
    float below = 0.0f, above = 0.0f;
    int nb = 0, na = 0;
    for (int i = 1; i <= k && v + i <= base; ++i, ++nb) below += profile_[static_cast<std::size_t>(v + i)];
    for (int i = 0; i < k && v - i >= 0; ++i, ++na) above += profile_[static_cast<std::size_t>(v - i)];
    below /= static_cast<float>(nb);
    above /= static_cast<float>(na);
    return std::pair<float, float>(below, above);
  };
  for (int v = base - 1; v >= top_row_; --v) {
    const auto [below, above] = step_at(v);
    const float t = std::max(thr, sig * std::sqrt(fvar));
    if (std::abs(below - above) > thr && std::abs(above - fmean) > t) {
      // The windows straddle a sharp edge first with one row of floor in the upper window:
      // refine to the strongest step within the next k - 1 rows up.
      int found = v;
      float best = std::abs(below - above);
      for (int j = v - 1; j > v - k && j >= top_row_; --j) {
        const auto [b2, a2] = step_at(j);
        if (std::abs(b2 - a2) > best) {
          best = std::abs(b2 - a2);
          found = j;
        }
      }
      return found;
    }
    const float x = profile_[static_cast<std::size_t>(v)];
    const float d = x - fmean;
    fmean += (1.0f - a) * d;
    fvar = a * (fvar + (1.0f - a) * d * d);
  }
  return -1;
}

const std::vector<SonarColumn>& VisualSonar::Process(GrayView image) {
  const int w = camera_.width;
  const int h = camera_.height;
  SQUINT_ENSURE(!image.Empty() && image.width == w && image.height == h,
                "visual sonar: the frame must be " + std::to_string(w) + "x" + std::to_string(h));
  const float thr = static_cast<float>(options_.step_threshold);
  MeasureWallLines(image);
  {
    const int rows = std::min(h, top_row_ + 1);
    std::fill(horizon_profile_.begin(), horizon_profile_.end(), 0.0f);
    for (int v = 0; v < rows; ++v) {
      const std::uint8_t* row = image.Row(v);
      for (int u = 0; u < w; ++u) horizon_profile_[static_cast<std::size_t>(u)] += row[u];
    }
    for (float& g : horizon_profile_) g /= static_cast<float>(rows);
  }
  for (int u = 0; u < w; ++u) {
    const int u0 = std::max(0, u - options_.column_half_width);
    const int u1 = std::min(w - 1, u + options_.column_half_width);
    const float norm = 1.0f / static_cast<float>(u1 - u0 + 1);
    for (int v = std::max(0, top_row_ - options_.step_window_rows); v < h; ++v) {
      const std::uint8_t* row = image.Row(v);
      int s = 0;
      for (int x = u0; x <= u1; ++x) s += row[x];
      profile_[static_cast<std::size_t>(v)] = static_cast<float>(s) * norm;
    }
    // Scan up from the bottom. The floor seen so far keeps a running mean and spread (rows
    // weighted toward the candidate, since the floor's shading changes with distance); row v is
    // the lowest non-floor row when the mean of the k rows from v upward differs from both the
    // k rows just below it and the running floor mean by more than the threshold, raised by
    // the floor's own texture spread (busy tiles).
    int found = FindStep(h - 1);
    // Too few floor rows below the step: no step.
    if (found >= 0 && h - 1 - found < options_.min_floor_rows) found = -1;
    // What lies above the step: a wall (or anything standing) rises from its base through the
    // horizon; a floor-material edge (tiles to carpet) is followed by more floor up to the next
    // boundary below the horizon. A second step, scanned up from the first with the region's own
    // running mean, at a floor range between floor_edge_min_ratio and floor_edge_max_ratio times
    // the first, makes the first a floor edge: the column then reads the second.
    edge_[static_cast<std::size_t>(u)] = 0.0;
    if (found >= 0 && options_.floor_edge_max_ratio > 0.0) {
      const int second = FindStep(found);
      if (second >= 0 && found - second >= options_.floor_edge_min_rows) {
        const double r1 = range_[static_cast<std::size_t>(found * w + u)];
        const double r2 = range_[static_cast<std::size_t>(second * w + u)];
        if (std::isfinite(r1) && std::isfinite(r2) && r1 >= options_.floor_edge_min_range_m && r1 < options_.max_range_m && r2 < options_.max_range_m &&
            r2 >= options_.floor_edge_min_ratio * r1 && r2 <= options_.floor_edge_max_ratio * r1) {
          edge_[static_cast<std::size_t>(u)] = r1;
          found = second;
        }
      }
    }
    // Raw range: 0 for a column blocked near, max_range_m for far.
    double r = 0.0;
    if (found >= 0) {
      r = range_[static_cast<std::size_t>(found * w + u)];
      if (!std::isfinite(r) || r > options_.max_range_m) r = options_.max_range_m;
    }
    raw_[static_cast<std::size_t>(u)] = r;
    rows_[static_cast<std::size_t>(u)] = found;
    // Mean of the bottom rows: the floor's look in columns with a clear boundary, the reference
    // for columns without any step.
    float bottom = 0.0f;
    for (int i = 0; i < options_.min_floor_rows + 1; ++i) bottom += profile_[static_cast<std::size_t>(h - 1 - i)];
    bottom_[static_cast<std::size_t>(u)] = bottom / static_cast<float>(options_.min_floor_rows + 1);
    // Mean of the two rows just below the horizon (far floor, or the wall's face at camera height).
    const int t0 = std::min(h - 1, top_row_ + 1);
    const int t1 = std::min(h - 1, top_row_ + 2);
    top_[static_cast<std::size_t>(u)] = 0.5f * (profile_[static_cast<std::size_t>(t0)] + profile_[static_cast<std::size_t>(t1)]);
  }
  // A column without any step is either filled by something near (a wall in the blind zone) or a
  // floor whose far boundary has too little contrast. Its bottom rows decide: unlike the floor
  // of this frame's columns with a clear boundary -> blocked near; like it -> unknown (no
  // information). Without such a reference (a wall fills the whole view) -> blocked near.
  // Only when enough columns have such a step (a few steps at the horizon may be a mortar line or
  // a seam on a wall that fills the view).
  // With floor_ref_boundaries, the columns whose step is a boundary in range first; far columns
  // (whose bottom may be something standing near, up to the horizon) only when those are too few.
  const int min_ref = std::max(3, options_.min_reference_columns);
  int n_ref = 0;
  for (int pass = options_.floor_ref_boundaries ? 0 : 1; pass < 2 && n_ref < min_ref; ++pass) {
    n_ref = 0;
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(u);
      const int found = rows_[i];
      if (found >= 0 && h - 1 - found >= reference_floor_rows_ && (pass == 1 || raw_[i] < options_.max_range_m))
        ref_window_[static_cast<std::size_t>(n_ref++)] = bottom_[i];
    }
  }
  float floor_ref = -1.0f;
  if (n_ref >= min_ref) {
    std::nth_element(ref_window_.begin(), ref_window_.begin() + n_ref / 2, ref_window_.begin() + n_ref);
    floor_ref = ref_window_[static_cast<std::size_t>(n_ref / 2)];
  }
  // Without a reference, a column whose grey changes smoothly by more than gradient_unknown_levels
  // from its bottom rows to the horizon shows the floor's perspective shading (a corridor whose
  // far boundaries have no contrast), not one surface filling the view: unknown.
  // A far step over a bottom unlike the floor (far_floor_max_diff) is no step: something standing
  // near fills the column up to the horizon, and the column is judged as the stepless ones. With
  // far_floor_from_m, steps in range from there on as well (the top edge of something a little
  // lower than the camera).
  const float gradient = static_cast<float>(options_.gradient_unknown_levels);
  const float far_limit = static_cast<float>(options_.far_floor_max_diff);
  const double far_from = options_.far_floor_from_m > 0.0 ? std::min(options_.far_floor_from_m, options_.max_range_m)
                                                           : options_.max_range_m;
  for (int u = 0; u < w; ++u) {
    const std::size_t i = static_cast<std::size_t>(u);
    unknown_[i] = 0;
    if (rows_[i] >= 0 && floor_ref >= 0.0f && far_limit > 0.0f && raw_[i] >= far_from &&
        std::abs(bottom_[i] - floor_ref) > far_limit) {
      rows_[i] = -1;
      raw_[i] = 0.0;
      edge_[i] = 0.0;
    }
    if (rows_[i] >= 0) continue;
    const bool unlike_floor = floor_ref < 0.0f ? !(gradient > 0.0f && std::abs(top_[i] - bottom_[i]) > gradient)
                                               : std::abs(bottom_[i] - floor_ref) > thr;
    if (!unlike_floor) {
      unknown_[i] = 1;
      raw_[i] = options_.max_range_m;
    }
  }
  // Median across neighbouring columns: anything standing that matters spans several columns,
  // while a texture step or a missed far step is usually one or two columns wide.
  const int m = options_.median_half_width;
  for (int u = 0; u < w; ++u) {
    const int u0 = std::max(0, u - m);
    const int u1 = std::min(w - 1, u + m);
    int n = 0;
    for (int x = u0; x <= u1; ++x) window_[static_cast<std::size_t>(n++)] = raw_[static_cast<std::size_t>(x)];
    std::nth_element(window_.begin(), window_.begin() + n / 2, window_.begin() + n);
    double r = window_[static_cast<std::size_t>(n / 2)];
    // Blocked near, and a boundary nearer than median_near_range_m, win one rank early (a wall
    // corner beside far floor, a chair leg close by: see median_near_bias).
    if (options_.median_near_bias > 0 && r > 0.0) {
      const int k = std::max(0, n / 2 - options_.median_near_bias);
      std::nth_element(window_.begin(), window_.begin() + k, window_.begin() + n / 2);
      if (window_[static_cast<std::size_t>(k)] <= 0.0) r = 0.0;
      else if (window_[static_cast<std::size_t>(k)] < options_.median_near_range_m) r = window_[static_cast<std::size_t>(k)];
    }
    SonarColumn& c = out_[static_cast<std::size_t>(u)];
    c.bearing_rad = bearing_[static_cast<std::size_t>(u)];
    c.range_m = r;
    c.own_range_m = raw_[static_cast<std::size_t>(u)];
    c.boundary_row = -1;
    c.floor_edge_m = 0.0;
    if (r <= 0.0) {
      c.kind = SonarReturn::kBlockedNear;
    } else if (r >= options_.max_range_m) {
      c.kind = unknown_[static_cast<std::size_t>(u)] ? SonarReturn::kUnknown : SonarReturn::kFar;
    } else {
      c.kind = SonarReturn::kBoundary;
      if (raw_[static_cast<std::size_t>(u)] == r) {
        c.boundary_row = rows_[static_cast<std::size_t>(u)];
        c.floor_edge_m = edge_[static_cast<std::size_t>(u)];
      }
    }
  }
  return out_;
}

}  // namespace squint::explore
