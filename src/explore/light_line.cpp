#include "squint/explore/light_line.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace squint::explore {

std::string LightLineOptions::Validate() const {
  if (min_level < 1 || min_level > 255) return "light line: min_level must be in [1, 255]";
  if (min_contrast < 1 || min_contrast > 255) return "light line: min_contrast must be in [1, 255]";
  if (!(min_relative_contrast >= 0.0 && min_relative_contrast < 1.0)) return "light line: min_relative_contrast must be in [0, 1)";
  if (max_side_difference < 0 || max_side_difference > 255) return "light line: max_side_difference must be in [0, 255]";
  if (min_rows < 3) return "light line: min_rows must be at least 3";
  if (!(min_span > 0.0) || !std::isfinite(min_span)) return "light line: min_span must be positive";
  if (!(max_residual_px > 0.0) || !std::isfinite(max_residual_px)) return "light line: max_residual_px must be positive";
  if (!(nominal_height_m > 0.0) || !std::isfinite(nominal_height_m)) return "light line: nominal_height_m must be positive";
  return {};
}

double LightLine::LateralM(double height_m) const { return -offset_ratio * std::cos(direction_rad) * height_m; }

namespace {

// One light point of an image row: its column and row (sub-pixel).
struct Peak {
  double u = 0.0;
  double v = 0.0;
};

// The light peaks of row v: local maxima at least min_level bright and min_contrast above both
// pixels two columns away (a light is one or two columns wide; a lit wall's pool is broad), at
// the centroid of the three columns around the maximum above that background.
int RowPeaks(const GrayView& img, int v, const LightLineOptions& o, Peak* out, int max_peaks) {
  const std::uint8_t* row = img.Row(v);
  int n = 0;
  for (int u = 2; u + 2 < img.width; ++u) {
    const int p = row[u];
    if (p < o.min_level || p < row[u - 1] || p <= row[u + 1]) continue;
    // Both sides two columns away: the ceiling around a light, alike (a lit door frame or a wall's
    // light pool has a wall of another grey on one side), and well below the peak.
    const int bg = std::max<int>(row[u - 2], row[u + 2]);
    if (p - bg < o.min_contrast || p - bg < o.min_relative_contrast * p ||
        std::abs(row[u - 2] - row[u + 2]) > o.max_side_difference)
      continue;
    double w_sum = 0.0, uw_sum = 0.0;
    for (int k = -1; k <= 1; ++k) {
      const double w = std::max(0, row[u + k] - bg);
      w_sum += w;
      uw_sum += w * (u + k);
    }
    if (n == max_peaks) return max_peaks + 1;  // too many: not a row of lights
    // The row of the light's centre at this column: a far light covers part of a row, and a
    // column's depth follows its row (the centroid over the rows beside it, above the same
    // background).
    double vw_sum = 0.0, v_w = 0.0;
    for (int k = -1; k <= 1; ++k) {
      if (v + k < 0 || v + k >= img.height) continue;
      const double w = std::max(0, img.Row(v + k)[u] - bg);
      vw_sum += w;
      v_w += w * (v + k);
    }
    out[n].u = uw_sum / w_sum;
    out[n].v = vw_sum > 0.0 ? v_w / vw_sum : v;
    ++n;
  }
  return n;
}

}  // namespace

LightLine FindLightLine(const GrayView& img, const CameraModel& camera, const LightLineOptions& o) {
  LightLine line;
  if (img.Empty() || img.width != camera.width || img.height != camera.height || img.width < 5) return line;
  const int top_rows = std::clamp(static_cast<int>(std::floor(camera.HorizonRow())), 0, img.height);
  // Per row: the light point's column and whether it is the midpoint of two peaks.
  struct RowPoint {
    double v = 0.0;
    double u = 0.0;
    int peaks = 0;
  };
  std::vector<RowPoint> points;
  points.reserve(static_cast<std::size_t>(top_rows));
  int two_peak_rows = 0, many_peak_rows = 0;
  for (int v = 0; v < top_rows; ++v) {
    Peak peaks[2];
    const int n = RowPeaks(img, v, o, peaks, 2);
    if (n == 1) points.push_back({peaks[0].v, peaks[0].u, 1});
    if (n == 2) {
      points.push_back({0.5 * (peaks[0].v + peaks[1].v), 0.5 * (peaks[0].u + peaks[1].u), 2});
      ++two_peak_rows;
    }
    if (n > 2) ++many_peak_rows;
  }
  // Two side rows of lights where several rows show both; then single peaks are ambiguous (one
  // row's light, or both merged far away) and only the pairs count (or, without side_rows, none).
  const bool pairs = two_peak_rows >= o.min_rows;
  if (pairs && !o.side_rows) return line;
  if (!pairs && two_peak_rows + many_peak_rows > o.max_multi_peak_rows) return line;
  const int use_peaks = pairs ? 2 : 1;
  // Weighted least squares of a = c0 + c1 b: a column error of δ pixels moves a by about b δ / f,
  // so each row weighs 1 / b².
  double sw = 0.0, sb = 0.0, sa = 0.0, sbb = 0.0, sba = 0.0, b_min = 1e300, b_max = -1e300;
  std::vector<Eigen::Vector2d> ab;
  ab.reserve(points.size());
  for (const RowPoint& p : points) {
    if (p.peaks != use_peaks) continue;
    const Eigen::Vector3d r = camera.PixelRayRobot(Eigen::Vector2d(p.u, p.v));
    if (r.z() <= 1e-6 || r.x() <= 1e-6) continue;
    const double b = r.x() / r.z(), a = r.y() / r.z();
    const double w = 1.0 / (b * b);
    sw += w;
    sb += w * b;
    sa += w * a;
    sbb += w * b * b;
    sba += w * b * a;
    b_min = std::min(b_min, b);
    b_max = std::max(b_max, b);
    ab.emplace_back(b, a);
  }
  line.rows = static_cast<int>(ab.size());
  line.side_rows = use_peaks == 2;
  if (line.rows < o.min_rows || b_max - b_min < o.min_span) return line;
  const double det = sw * sbb - sb * sb;
  if (!(det > 0.0)) return line;
  const double c1 = (sw * sba - sb * sa) / det;
  const double c0 = (sa - c1 * sb) / sw;
  // The worst residual, as pixels at the row's depth.
  double worst_px = 0.0;
  for (const Eigen::Vector2d& p : ab) worst_px = std::max(worst_px, std::abs(p.y() - (c0 + c1 * p.x())) * camera.fx / p.x());
  line.residual_px = worst_px;
  if (!std::isfinite(c0) || !std::isfinite(c1) || worst_px > o.max_residual_px) return line;
  line.offset_ratio = c0;
  line.direction_rad = std::atan(c1);
  line.valid = true;
  return line;
}

}  // namespace squint::explore
