#include "squint/explore/wall_lines.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include <Eigen/Eigenvalues>

#include "squint/core/angles.hpp"

namespace squint::explore {

std::string WallLineOptions::Validate() const {
  if (below_rows < 2 || below_rows > 64) return "wall lines: below_rows must be in [2, 64]";
  if (above_rows < 2 || above_rows > 64) return "wall lines: above_rows must be in [2, 64]";
  if (!(smooth_ratio > 0.0 && smooth_ratio < 1.0)) return "wall lines: smooth_ratio must be in (0, 1)";
  if (!(min_floor_texture > 0.0) || !std::isfinite(min_floor_texture)) return "wall lines: min_floor_texture must be positive";
  if (!(floor_texture_fraction >= 0.0 && floor_texture_fraction <= 1.0))
    return "wall lines: floor_texture_fraction must be in [0, 1]";
  if (!(std::abs(base_row_offset) <= 4.0)) return "wall lines: base_row_offset must be in [-4, 4]";
  if (reference_rows < 1 || reference_rows > 64) return "wall lines: reference_rows must be in [1, 64]";
  if (!(max_range_m > 0.0) || !std::isfinite(max_range_m)) return "wall lines: max_range_m must be positive";
  if (!(inlier_m > 0.0) || !std::isfinite(inlier_m)) return "wall lines: inlier_m must be positive";
  if (!(parallel_bin_m > 0.0) || !std::isfinite(parallel_bin_m)) return "wall lines: parallel_bin_m must be positive";
  if (!(min_pair_m > 0.0) || !std::isfinite(min_pair_m)) return "wall lines: min_pair_m must be positive";
  if (samples < 1 || samples > 100000) return "wall lines: samples must be in [1, 100000]";
  if (min_inliers < 3) return "wall lines: min_inliers must be at least 3";
  if (min_rows < 1) return "wall lines: min_rows must be at least 1";
  if (foot_points < 1 || foot_points > 10000) return "wall lines: foot_points must be in [1, 10000]";
  if (!(min_span_m >= 0.0) || !std::isfinite(min_span_m)) return "wall lines: min_span_m must be non-negative";
  return {};
}

double WallLines::HeadingDeg() const {
  const double h = -RadToDeg(direction_rad);
  return h - 90.0 * std::floor((h + 45.0) / 90.0);
}

namespace {

// A parallel line is sought only this far or farther from the main one (nearer groups are the
// same wall's scatter).
constexpr double kMinParallelGapM = 0.5;

struct Hypothesis {
  int score = -1;
  Eigen::Vector2d dir{1.0, 0.0};
  Eigen::Vector2d origin{0.0, 0.0};
};

// The points' signed distances from the line through `origin` along `dir`.
void Residuals(const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
               std::vector<double>* r) {
  const Eigen::Vector2d n(-dir.y(), dir.x());
  r->resize(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) (*r)[k] = n.dot(pts[k] - origin);
}

// The most populated bin of offsets at least kMinParallelGapM from zero: its count, and the
// offsets' median in it (via `centre`).
int ParallelBin(const std::vector<double>& r, double inlier_m, double bin_m, double* centre) {
  std::vector<double> far;
  far.reserve(r.size());
  for (double x : r)
    if (std::abs(x) >= kMinParallelGapM && std::abs(x) > inlier_m) far.push_back(x);
  if (far.empty()) return 0;
  std::sort(far.begin(), far.end());
  // Sliding window of width bin_m over the sorted offsets (ties go to the first, lowest window).
  int best = 0;
  std::size_t best_lo = 0, best_hi = 0;
  for (std::size_t lo = 0, hi = 0; lo < far.size(); ++lo) {
    while (hi < far.size() && far[hi] - far[lo] <= bin_m) ++hi;
    if (static_cast<int>(hi - lo) > best) best = static_cast<int>(hi - lo), best_lo = lo, best_hi = hi;
  }
  *centre = far[best_lo + (best_hi - best_lo - 1) / 2];
  return best;
}

}  // namespace

WallLines FindWallLines(const GrayView& image, const CameraModel& camera, const WallLineOptions& o,
                        std::vector<Eigen::Vector2d>* base_points) {
  WallLines out;
  if (base_points) base_points->clear();
  const int w = image.width, h = image.height;
  if (image.Empty() || w < 3 || h < o.below_rows + o.above_rows + 4) return out;

  // Texture: the vertical second difference's magnitude, averaged over three columns; summed up
  // each column (cum[v * w + u] = the sum over rows above v).
  std::vector<float> tex(static_cast<std::size_t>(w) * h, 0.0f);
  for (int v = 1; v + 1 < h; ++v) {
    const std::uint8_t* up = image.Row(v - 1);
    const std::uint8_t* mid = image.Row(v);
    const std::uint8_t* dn = image.Row(v + 1);
    float* t = &tex[static_cast<std::size_t>(v) * w];
    for (int u = 0; u < w; ++u) t[u] = static_cast<float>(std::abs(up[u] + dn[u] - 2 * mid[u]));
  }
  std::vector<float> row(static_cast<std::size_t>(w));
  for (int v = 1; v + 1 < h; ++v) {
    float* t = &tex[static_cast<std::size_t>(v) * w];
    std::copy(t, t + w, row.begin());
    for (int u = 0; u < w; ++u) {
      const int a = std::max(0, u - 1), b = std::min(w - 1, u + 1);
      float s = 0.0f;
      for (int k = a; k <= b; ++k) s += row[static_cast<std::size_t>(k)];
      t[u] = s / static_cast<float>(b - a + 1);
    }
  }
  std::vector<double> cum(static_cast<std::size_t>(w) * (h + 1), 0.0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      cum[static_cast<std::size_t>(v + 1) * w + u] = cum[static_cast<std::size_t>(v) * w + u] + tex[static_cast<std::size_t>(v) * w + u];
  auto mean_rows = [&](int u, int from, int to) {  // rows [from, to)
    return (cum[static_cast<std::size_t>(to) * w + u] - cum[static_cast<std::size_t>(from) * w + u]) / (to - from);
  };

  out.bottom_texture.resize(static_cast<std::size_t>(w));
  for (int u = 0; u < w; ++u)
    out.bottom_texture[static_cast<std::size_t>(u)] = static_cast<float>(mean_rows(u, h - 1 - o.below_rows, h - 1));

  // The floor's reference texture: the median over the bottom rows (without the last, which has
  // no second difference).
  std::vector<float> ref;
  const int ref_from = std::max(1, h - 1 - o.reference_rows);
  for (int v = ref_from; v < h - 1; ++v) ref.insert(ref.end(), &tex[static_cast<std::size_t>(v) * w], &tex[static_cast<std::size_t>(v) * w] + w);
  std::nth_element(ref.begin(), ref.begin() + static_cast<std::ptrdiff_t>(ref.size() / 2), ref.end());
  const double floor_min = std::max(o.min_floor_texture, o.floor_texture_fraction * ref[ref.size() / 2]);

  // Each column's wall base: scanning up, the first row with textured floor just below it and a
  // smooth stretch just above it. Rows at or above the horizon (+2) see no floor.
  const int top = std::max(1, static_cast<int>(std::floor(camera.HorizonRow())) + 2);
  std::vector<Eigen::Vector2d> pts;
  std::vector<int> pt_rows;
  pts.reserve(static_cast<std::size_t>(w));
  pt_rows.reserve(static_cast<std::size_t>(w));
  for (int u = 0; u < w; ++u) {
    for (int v = h - 2 - o.below_rows; v > top; --v) {
      const double below = mean_rows(u, v + 1, v + 1 + o.below_rows);
      if (below < floor_min) continue;
      const int lo = std::max(1, v - o.above_rows);
      if (v - lo < 2) break;
      const double above = mean_rows(u, lo, v);
      if (above < o.smooth_ratio * below) {
        // The smooth stretch's mean lets a row or two of floor texture through: the base is above
        // the highest of those rows still textured (at most half the stretch up).
        int b = v;
        while (b - 1 > top && b > v - o.above_rows / 2 &&
               tex[static_cast<std::size_t>(b - 1) * w + u] >= o.smooth_ratio * below)
          --b;
        if (const auto p = camera.FloorPoint({static_cast<double>(u), b - 0.5 + o.base_row_offset}); p && p->norm() <= o.max_range_m)
          pts.push_back(*p), pt_rows.push_back(b);
        break;
      }
    }
  }
  if (base_points) *base_points = pts;
  out.points = static_cast<int>(pts.size());
  int n = out.points;
  if (n < o.min_inliers) return out;

  // Two attempts at most (drop_one_row_line); all_pts keeps every point for the foot across the
  // corridor when the second leaves some out.
  std::vector<Eigen::Vector2d> all_pts;
  Eigen::Vector2d dir, origin;
  double par_centre = 0.0, ss = 0.0, par_mean = 0.0;
  int inl = 0, pinl = 0;
  std::vector<double> r;
  for (int attempt = 0; attempt < 2; ++attempt) {
    // Sampled pairs (a fixed sequence: the same image gives the same lines).
    Hypothesis best;
    const double bin = o.parallel_bin_m;
    for (int s = 0; s < o.samples; ++s) {
      const int i = static_cast<int>((static_cast<long long>(s) * 7919) % n);
      const int j = static_cast<int>((i + 1 + (static_cast<long long>(s) * 104729) % (n - 1)) % n);
      Eigen::Vector2d d = pts[static_cast<std::size_t>(j)] - pts[static_cast<std::size_t>(i)];
      const double len = d.norm();
      if (len < o.min_pair_m) continue;
      d /= len;
      Residuals(pts, pts[static_cast<std::size_t>(i)], d, &r);
      int hits = 0;
      for (double x : r) hits += std::abs(x) < o.inlier_m;
      double centre = 0.0;
      const int score = hits + ParallelBin(r, o.inlier_m, bin, &centre);
      if (score > best.score) best = {score, d, pts[static_cast<std::size_t>(i)]};
    }
    if (best.score < 0) return out;

    // Refine: both groups' pooled scatter about their own means gives the direction (twice, the
    // groups taken again about the refined lines).
    dir = best.dir;
    origin = best.origin;
    par_centre = 0.0;
    std::vector<int> group(static_cast<std::size_t>(n));
    for (int round = 0; round < 2; ++round) {
      Residuals(pts, origin, dir, &r);
      const int par = ParallelBin(r, o.inlier_m, bin, &par_centre);
      Eigen::Vector2d mean[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
      int count[2] = {0, 0};
      for (int k = 0; k < n; ++k) {
        const double x = r[static_cast<std::size_t>(k)];
        int g = -1;
        if (std::abs(x) < o.inlier_m) g = 0;
        else if (par > 0 && std::abs(x - par_centre) < o.inlier_m) g = 1;
        group[static_cast<std::size_t>(k)] = g;
        if (g >= 0) mean[g] += pts[static_cast<std::size_t>(k)], ++count[g];
      }
      if (count[0] < 2) return out;
      for (int g = 0; g < 2; ++g)
        if (count[g] > 0) mean[g] /= count[g];
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      for (int k = 0; k < n; ++k) {
        const int g = group[static_cast<std::size_t>(k)];
        if (g < 0 || count[g] < 2) continue;
        const Eigen::Vector2d q = pts[static_cast<std::size_t>(k)] - mean[g];
        scatter += q * q.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
      Eigen::Vector2d nd = eig.eigenvectors().col(1);
      if (nd.dot(dir) < 0.0) nd = -nd;
      dir = nd;
      origin = mean[0];
    }

    // The final groups about the refined lines.
    Residuals(pts, origin, dir, &r);
    const int par = ParallelBin(r, o.inlier_m, bin, &par_centre);
    double lo = 1e300, hi = -1e300, par_sum = 0.0;
    int row_lo = h, row_hi = -1;
    ss = 0.0;
    inl = pinl = 0;
    for (int k = 0; k < n; ++k) {
      const double x = r[static_cast<std::size_t>(k)];
      if (std::abs(x) < o.inlier_m) {
        ++inl;
        ss += x * x;
        const double along = dir.dot(pts[static_cast<std::size_t>(k)]);
        lo = std::min(lo, along), hi = std::max(hi, along);
        row_lo = std::min(row_lo, pt_rows[static_cast<std::size_t>(k)]);
        row_hi = std::max(row_hi, pt_rows[static_cast<std::size_t>(k)]);
      } else if (par > 0 && std::abs(x - par_centre) < o.inlier_m) {
        ++pinl;
        par_sum += x;
      }
    }
    par_mean = pinl > 0 ? par_sum / pinl : 0.0;
    for (int k = 0; k < n && pinl > 0; ++k) {
      const double x = r[static_cast<std::size_t>(k)];
      if (std::abs(x) >= o.inlier_m && std::abs(x - par_centre) < o.inlier_m) ss += (x - par_mean) * (x - par_mean);
    }
    out.inliers = inl;
    out.parallel_inliers = pinl;
    // Points of one image row lie on a line across the view whatever the walls do (where a far
    // floor's texture fades out): such a line says nothing of the direction.
    if (inl >= o.min_inliers && row_hi - row_lo + 1 < o.min_rows && o.drop_one_row_line && attempt == 0) {
      // The best line is one image row's points (a far foot across the view, an end wall's): it
      // says nothing of the direction, but it can outnumber a near wall's base beside it. Its
      // points are left out and the lines sought again among the rest.
      all_pts = pts;
      std::size_t keep = 0;
      for (int k = 0; k < n; ++k) {
        if (std::abs(r[static_cast<std::size_t>(k)]) < o.inlier_m) continue;
        pts[keep] = pts[static_cast<std::size_t>(k)];
        pt_rows[keep] = pt_rows[static_cast<std::size_t>(k)];
        ++keep;
      }
      pts.resize(keep);
      pt_rows.resize(keep);
      n = static_cast<int>(keep);
      if (n < o.min_inliers) return out;
      continue;
    }
    if (inl < o.min_inliers || hi - lo < o.min_span_m || row_hi - row_lo + 1 < o.min_rows) return out;
    break;
  }
  double theta = std::atan2(dir.y(), dir.x());
  if (theta <= -kPi / 2) theta += kPi;
  if (theta > kPi / 2) theta -= kPi;
  const Eigen::Vector2d d(std::cos(theta), std::sin(theta));
  const Eigen::Vector2d left(-d.y(), d.x());
  const double sign = left.dot(Eigen::Vector2d(-dir.y(), dir.x())) >= 0.0 ? 1.0 : -1.0;
  out.valid = true;
  out.direction_rad = theta;
  out.offset_m = left.dot(origin);
  out.parallel_offset_m = pinl > 0 ? out.offset_m + sign * par_mean : 0.0;
  out.rms_m = std::sqrt(ss / (inl + pinl));
  // The corridor ahead: both walls' lines with the robot between them; a foot between them (an end
  // wall's or an obstacle's: at least foot_points points on neither line) ends it, else the range
  // used. Fewer stray points are a textured floor's own edges (tile joints, a carpet's blotches).
  if (pinl > 0 && out.offset_m * out.parallel_offset_m < 0.0) {
    const double lo_off = std::min(out.offset_m, out.parallel_offset_m) + o.inlier_m;
    const double hi_off = std::max(out.offset_m, out.parallel_offset_m) - o.inlier_m;
    std::vector<double> between;
    const std::vector<Eigen::Vector2d>& foot_pts = all_pts.empty() ? pts : all_pts;
    if (!all_pts.empty()) Residuals(all_pts, origin, dir, &r);
    for (std::size_t k = 0; k < foot_pts.size(); ++k) {
      const double x = r[k];
      const Eigen::Vector2d& q = foot_pts[k];
      const double along = d.dot(q), across = left.dot(q);
      if (std::abs(x) >= o.inlier_m && std::abs(x - par_centre) >= o.inlier_m && along > 0.0 && across > lo_off && across < hi_off)
        between.push_back(along);
    }
    out.corridor_ahead_m = o.max_range_m;
    if (static_cast<int>(between.size()) >= o.foot_points) {
      std::nth_element(between.begin(), between.begin() + (o.foot_points - 1), between.end());
      out.corridor_ahead_m = between[static_cast<std::size_t>(o.foot_points - 1)];
    }
  }
  return out;
}

}  // namespace squint::explore
