// The five heading cues of paper §4.1 (f1 entropy, f2 symmetry, f3 phase, f4 vanishing point,
// f5 bright pixels), each scoring the glance's columns without allocating.
#include "squint/corridor/heading_measures.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "curve_peak.hpp"
#include "squint/core/error.hpp"
#include "squint/corridor/information.hpp"

namespace squint::corridor {
namespace {

constexpr int kW = kGlanceWidth;
constexpr int kH = kGlanceHeight;
constexpr int kMaxColumnBins = 16;  // column_bits ≤ 4
constexpr int kMaxVanishingBins = 16;

void SetNoEstimate(HeadingMeasureResult& out, Reason reason) {
  out.column_px.reset();
  out.confidence = 0.0;
  out.reason = reason;
}

void SetFromPeak(const detail::Peak& peak, HeadingMeasureResult& out) {
  if (peak.reason != Reason::kNone) {
    SetNoEstimate(out, peak.reason);
    return;
  }
  out.column_px = peak.column;
  out.confidence = std::clamp(peak.prominence, 0.0, 1.0);
  out.reason = Reason::kNone;
}

// Bit k set when counts[k] != 0, for count ≤ 64 counts.
inline std::uint64_t OccupiedMask(const std::uint16_t* counts, int count) {
  std::uint64_t mask = 0;
  int k = 0;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  for (; k + 16 <= count; k += 16) {
    const __m128i lo = _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(counts + k)), zero);
    const __m128i hi = _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(counts + k + 8)), zero);
    const unsigned empty = static_cast<unsigned>(_mm_movemask_epi8(_mm_packs_epi16(lo, hi)));
    mask |= static_cast<std::uint64_t>(~empty & 0xFFFFu) << k;
  }
#endif
  for (; k < count; ++k) mask |= static_cast<std::uint64_t>(counts[k] != 0) << k;
  return mask;
}

// Miller–Madow-corrected mutual information from a joint histogram with N < kNLogNTableSize
// samples, using the n·log n table t: MI = (Σ t(n_ab) − Σ t(n_a) − Σ t(n_b) + t(N)) / N, minus the
// bias (B_a − 1)(B_b − 1) / 2N of the plug-in estimate (B = occupied bins).
// Only occupied bins are visited, in ascending index order: t(0) = 0 adds nothing, so the sum is
// bit-identical to the full scan.
inline double CorrectedMutualInformation(const std::uint16_t* joint, int bins, std::uint32_t n, const double* t) {
  if (n == 0) return 0.0;
  std::uint32_t row[kMaxVanishingBins] = {}, col[kMaxVanishingBins] = {};
  double s = 0.0;
  const int cells = bins * bins;
  const int bits = std::countr_zero(static_cast<unsigned>(bins));
  for (int base = 0; base < cells; base += 64) {
    for (std::uint64_t mask = OccupiedMask(joint + base, std::min(64, cells - base)); mask != 0; mask &= mask - 1) {
      const int k = base + std::countr_zero(mask);
      const std::uint16_t c = joint[k];
      row[k >> bits] += c;
      col[k & (bins - 1)] += c;
      s += t[c];
    }
  }
  int ra = 0, cb = 0;
  for (int a = 0; a < bins; ++a) {
    s -= t[row[a]] + t[col[a]];
    ra += row[a] > 0;
    cb += col[a] > 0;
  }
  s += t[n];
  return s / n - (ra - 1) * (cb - 1) / (2.0 * n);
}

// atan for the phase cue: a minimax polynomial on [−1, 1] (error < 2e-5 rad), folded outside.
inline double FastAtan(double z) {
  const bool fold = std::abs(z) > 1.0;
  const double x = fold ? 1.0 / z : z;
  const double x2 = x * x;
  const double p =
      x * (0.99997726 + x2 * (-0.33262347 + x2 * (0.19354346 + x2 * (-0.11643287 + x2 * (0.05265332 + x2 * -0.01172120)))));
  if (!fold) return p;
  return (z > 0.0 ? 1.5707963267948966 : -1.5707963267948966) - p;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// f1: column entropy (§4.1.1).
void EntropyHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  if (g.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  const int bins = 1 << options_.column_bits;
  std::uint32_t column_hist[kW][kMaxColumnBins] = {};
  for (int v = 0; v < kH; ++v) {
    const std::uint8_t* row = g.column_level.data() + v * kW;
    for (int u = 0; u < kW; ++u) ++column_hist[u][row[u]];
  }
  const int r = options_.slice_width_px / 2;
  for (int x = 0; x < kW; ++x) {
    std::uint32_t hist[kMaxColumnBins] = {};
    const int a = std::max(0, x - r), b = std::min(kW - 1, x + r);
    for (int u = a; u <= b; ++u)
      for (int k = 0; k < bins; ++k) hist[k] += column_hist[u][k];
    out.curve[x] = static_cast<float>(EntropyFromCounts(hist, bins, static_cast<std::uint32_t>((b - a + 1) * kH)));
  }
  SetFromPeak(detail::FindPeak(out.curve, 0, kW - 1, options_.border_px, options_.min_prominence), out);
}

// ---------------------------------------------------------------------------------------------
// f2: mirror symmetry by mutual information (§4.1.2, eq. 2). The axis at column x pairs pixel
// (x − d, v) with (x + d, v) for d = 1..D, D = min(half_width, x, 31 − x); axes with
// D < min_half_width are not scored. The bias correction keeps narrow windows (few pairs, whose
// plug-in MI is inflated) comparable with wide ones.
void SymmetryHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  if (g.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  const int bins = 1 << options_.column_bits;
  const int dmin = options_.symmetry_min_half_width_px;
  const double* table = NLogNTable();
  const bool significance = options_.symmetry_significance;
  float lowest = 0.0f;
  bool any = false;
  int first = kW, last = -1;
  for (int x = dmin; x <= kW - 1 - dmin; ++x) {
    const int d_max = std::min({options_.symmetry_half_width_px, x, kW - 1 - x});
    // Four interleaved histograms (one per row of a group of four) break the store-to-load
    // chains of neighbouring pairs, which usually fall in the same bin.
    // They are packed with stride bins², so only the used part is cleared.
    std::uint16_t joint[4][kMaxColumnBins * kMaxColumnBins];
    if (bins <= 8)
      std::memset(joint, 0, sizeof(std::uint16_t) * 4 * 64);  // fixed size: inlined stores
    else
      std::memset(joint, 0, sizeof(std::uint16_t) * 4 * bins * bins);
    std::uint16_t* j0 = joint[0];
    std::uint16_t* j1 = j0 + bins * bins;
    std::uint16_t* j2 = j1 + bins * bins;
    std::uint16_t* j3 = j2 + bins * bins;
    for (int v = 0; v < kH; v += 4) {
      const std::uint8_t* r0 = g.column_level.data() + v * kW + x;
      const std::uint8_t* r1 = r0 + kW;
      const std::uint8_t* r2 = r1 + kW;
      const std::uint8_t* r3 = r2 + kW;
      for (int d = 1; d <= d_max; ++d) {
        ++j0[r0[-d] * bins + r0[d]];
        ++j1[r1[-d] * bins + r1[d]];
        ++j2[r2[-d] * bins + r2[d]];
        ++j3[r3[-d] * bins + r3[d]];
      }
    }
    for (int k = 0; k < bins * bins; ++k) j0[k] = static_cast<std::uint16_t>(j0[k] + j1[k] + j2[k] + j3[k]);
    const double mi = CorrectedMutualInformation(j0, bins, static_cast<std::uint32_t>(d_max * kH), table);
    out.curve[x] = static_cast<float>(significance ? mi * d_max / options_.symmetry_half_width_px : mi);
    lowest = any ? std::min(lowest, out.curve[x]) : out.curve[x];
    any = true;
    first = std::min(first, x);
    last = std::max(last, x);
  }
  if (!any) return SetNoEstimate(out, Reason::kFlatCurve);
  // Unscored columns hold the lowest score so that they never look like peaks.
  for (int x = 0; x < kW; ++x)
    if (x < first || x > last) out.curve[x] = lowest;
  SetFromPeak(detail::FindPeak(out.curve, first, last, options_.border_px, options_.min_prominence), out);
}

// ---------------------------------------------------------------------------------------------
// f3: aggregate gradient phase (§4.1.3). The phase atan(gy / gx) ∈ (−90°, 90°) of a mirrored
// edge is the negative of the original's, so over a window centred on the corridor's axis the
// phases cancel. AP(x) is the mean phase over the window [x − D, x + D] (D as for symmetry);
// the estimate is the zero crossing of AP with the steepest slope.
void PhaseHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  if (g.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  if (options_.phase_line_vote) return MeasureLineVote(g, out);
  MeasureBalance(g, out);
}

// Line vote: an edge pixel (u, v) with Sobel gradient (gx, gy) lies on a line of direction
// (−gy, gx), which crosses the horizon row v_h at x = u − (v_h − v)·gy/gx. The lines of the
// corridor's parallel edges (wall–floor, wall–ceiling, light rows, floor joints) all cross it at
// the vanishing point; vertical edges (door frames) would vote for their own column and
// horizontal ones (the end wall) far outside, so both are left out. Each vote, weighted by the
// gradient magnitude, is split linearly between the two nearest columns; the curve is the votes
// smoothed by [1 2 1], and its maximum is the estimate.
void PhaseHeading::MeasureLineVote(const PreparedGlance& g, HeadingMeasureResult& out) const {
  const double min_mag = 8.0 * options_.phase_min_gradient;
  const int min_mag2 = static_cast<int>(std::ceil(min_mag * min_mag));
  const float tan_vertical =
      static_cast<float>(std::tan(options_.phase_min_vertical_deg * 3.14159265358979323846 / 180.0));
  const float horizon = static_cast<float>(horizon_row_ ? *horizon_row_ : (kH - 1) / 2.0);
  const float min_rows = static_cast<float>(options_.phase_min_horizon_rows);
  // votes[i + 1] holds column i; the two guard cells take the halves of votes just outside.
  float votes[kW + 2] = {};
  float total = 0.0f;
  for (int v = 1; v < kH - 1; ++v) {
    const float lever = horizon - static_cast<float>(v);
    if (std::abs(lever) < min_rows) continue;
    const std::int16_t* gxr = g.grad_x.data() + v * kW;
    const std::int16_t* gyr = g.grad_y.data() + v * kW;
    for (int u = 1; u < kW - 1; ++u) {
      const int gx = gxr[u], gy = gyr[u];
      const int m2 = gx * gx + gy * gy;
      if (m2 < min_mag2 || gx == 0) continue;
      const float fgx = static_cast<float>(gx), fgy = static_cast<float>(gy);
      if (std::abs(fgy) < tan_vertical * std::abs(fgx)) continue;  // near-vertical edge
      const float x = static_cast<float>(u) - lever * fgy / fgx;
      if (!(x > -1.0f && x < static_cast<float>(kW))) continue;
      const float w = std::sqrt(static_cast<float>(m2));
      const float xf = std::floor(x);
      const int i = static_cast<int>(xf);
      const float f = x - xf;
      votes[i + 1] += w * (1.0f - f);
      votes[i + 2] += w * f;
      total += w;
    }
  }
  if (!(total > 0.0f)) return SetNoEstimate(out, Reason::kZeroGradient);
  for (int x = 0; x < kW; ++x) out.curve[x] = votes[x] + 2.0f * votes[x + 1] + votes[x + 2];
  SetFromPeak(detail::FindPeak(out.curve, 0, kW - 1, options_.border_px, options_.min_prominence), out);
}

void PhaseHeading::MeasureBalance(const PreparedGlance& g, HeadingMeasureResult& out) const {
  // Sobel units are 8 × grey levels per pixel.
  const double min_mag = 8.0 * options_.phase_min_gradient;
  const int min_mag2 = static_cast<int>(std::ceil(min_mag * min_mag));
  const double tan_max = std::tan(options_.phase_max_deg * 3.14159265358979323846 / 180.0);
  double column_sum[kW] = {};
  int column_count[kW] = {};
  int total = 0;
  for (int v = 1; v < kH - 1; ++v) {
    for (int u = 1; u < kW - 1; ++u) {
      const int gx = g.grad_x[v * kW + u], gy = g.grad_y[v * kW + u];
      if (gx * gx + gy * gy < min_mag2) continue;
      if (std::abs(gy) > tan_max * std::abs(gx)) continue;  // near-horizontal edge: phase ±90° ambiguous
      column_sum[u] += FastAtan(static_cast<double>(gy) / gx);
      ++column_count[u];
      ++total;
    }
  }
  if (total == 0) return SetNoEstimate(out, Reason::kZeroGradient);
  const int dmin = options_.symmetry_min_half_width_px;
  double ap[kW] = {};
  bool scored[kW] = {};
  for (int x = dmin; x <= kW - 1 - dmin; ++x) {
    const int d = std::min({options_.symmetry_half_width_px, x, kW - 1 - x});
    double s = 0.0;
    int n = 0;
    for (int u = x - d; u <= x + d; ++u) {
      s += column_sum[u];
      n += column_count[u];
    }
    if (n == 0) continue;
    ap[x] = s / n;
    scored[x] = true;
    out.curve[x] = static_cast<float>(-std::abs(ap[x]));
  }
  // The steepest sign change between neighbouring scored columns.
  double best_slope = 0.0, best_col = 0.0;
  bool found = false;
  for (int x = 0; x + 1 < kW; ++x) {
    if (!scored[x] || !scored[x + 1]) continue;
    const double a = ap[x], b = ap[x + 1];
    if ((a > 0.0) == (b > 0.0) && a != 0.0 && b != 0.0) continue;
    const double slope = std::abs(b - a);
    if (!found || slope > best_slope) {
      best_slope = slope;
      best_col = (a == b) ? x : x + a / (a - b);
      found = true;
    }
  }
  if (!found) return SetNoEstimate(out, Reason::kFlatCurve);
  // Confidence: the slope relative to the curve's range (a clean crossing spans it).
  double lo = 0.0, hi = 0.0;
  for (int x = 0; x < kW; ++x)
    if (scored[x]) lo = std::min(lo, ap[x]), hi = std::max(hi, ap[x]);
  out.column_px = best_col;
  out.confidence = hi > lo ? std::clamp(best_slope / (hi - lo), 0.0, 1.0) : 0.0;
  out.reason = Reason::kNone;
}

// ---------------------------------------------------------------------------------------------
// f4: vanishing point by self-similarity (§4.1.4). The half-size glance S (2×2 means) placed at
// offset (ox, oy) covers glance pixels ox..ox+15, oy..oy+11; S's pixel i has its centre at glance
// coordinate 2i + 0.5, so glance content at x appears at ox + (x − 0.5) / 2. The lines joining
// each glance corner to the corresponding corner of the placed S meet at the fixed point of that
// map, x = 2·ox − 0.5 (and y = 2·oy − 0.5): the vanishing point. The search is coarse-to-fine over ox and bounded in oy.
void VanishingHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  if (g.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  constexpr int kSw = kW / 2, kSh = kH / 2;
  const int bins = 1 << options_.vanishing_bits;
  const int shift = 8 - options_.vanishing_bits;
  // S's levels pre-multiplied by the bin count: the joint index is small_row[i] + level.
  std::uint8_t small[kSw * kSh];
  for (int j = 0; j < kSh; ++j) {
    for (int i = 0; i < kSw; ++i) {
      const std::uint8_t* p = g.glance.pixels.data() + 2 * j * kW + 2 * i;
      const int mean = (p[0] + p[1] + p[kW] + p[kW + 1] + 2) >> 2;
      small[j * kSw + i] = static_cast<std::uint8_t>((mean >> shift) * bins);
    }
  }
  // Rows of offsets to search.
  int oy_lo = 0, oy_hi = kH - kSh;
  if (horizon_row_) {
    const double centre = (*horizon_row_ + 0.5) / 2.0;
    const double margin = options_.vanishing_row_margin_px / 2.0;
    oy_lo = std::clamp(static_cast<int>(std::floor(centre - margin)), 0, kH - kSh);
    oy_hi = std::clamp(static_cast<int>(std::ceil(centre + margin)), 0, kH - kSh);
  }
  constexpr int kOx = kW - kSw + 1;  // 17 offsets
  float score[kOx][kH - kSh + 1];
  bool done[kOx][kH - kSh + 1] = {};
  const std::uint8_t* level = g.vanishing_level.data();
  const double* table = NLogNTable();
  auto evaluate = [&](int ox, int oy) -> float {
    if (done[ox][oy]) return score[ox][oy];
    // Four interleaved histograms break the store-to-load chains on repeated bins.
    std::uint16_t joint[4][kMaxVanishingBins * kMaxVanishingBins];
    if (bins <= 8)
      std::memset(joint, 0, sizeof(std::uint16_t) * 4 * 64);  // fixed size: inlined stores
    else
      std::memset(joint, 0, sizeof(std::uint16_t) * 4 * bins * bins);
    std::uint16_t* j0 = joint[0];
    std::uint16_t* j1 = joint[0] + bins * bins;
    std::uint16_t* j2 = j1 + bins * bins;
    std::uint16_t* j3 = j2 + bins * bins;
    for (int j = 0; j < kSh; ++j) {
      const std::uint8_t* a = small + j * kSw;
      const std::uint8_t* b = level + (oy + j) * kW + ox;
      for (int i = 0; i < kSw; i += 4) {
        ++j0[a[i] + b[i]];
        ++j1[a[i + 1] + b[i + 1]];
        ++j2[a[i + 2] + b[i + 2]];
        ++j3[a[i + 3] + b[i + 3]];
      }
    }
    for (int k = 0; k < bins * bins; ++k) j0[k] = static_cast<std::uint16_t>(j0[k] + j1[k] + j2[k] + j3[k]);
    const float mi = static_cast<float>(CorrectedMutualInformation(j0, bins, kSw * kSh, table));
    done[ox][oy] = true;
    score[ox][oy] = mi;
    return mi;
  };
  int best_ox = 0, best_oy = oy_lo;
  float best = -1e30f;
  // Every horizontal offset (the MI peak is about one offset wide, too sharp for a coarse grid)
  // over the bounded rows.
  for (int oy = oy_lo; oy <= oy_hi; ++oy) {
    for (int ox = 0; ox < kOx; ++ox) {
      const float s = evaluate(ox, oy);
      if (s > best) best = s, best_ox = ox, best_oy = oy;
    }
  }
  // Curve: the best score of each column's candidate vanishing point, spread to both columns.
  std::array<float, kOx> by_ox{};
  by_ox.fill(-1e30f);
  for (int ox = 0; ox < kOx; ++ox)
    for (int oy = oy_lo; oy <= oy_hi; ++oy)
      if (done[ox][oy]) by_ox[ox] = std::max(by_ox[ox], score[ox][oy]);
  float lo = best;
  for (int ox = 0; ox < kOx; ++ox)
    if (by_ox[ox] > -1e29f) lo = std::min(lo, by_ox[ox]);
  for (int ox = 0; ox < kOx; ++ox) {
    const float s = by_ox[ox] > -1e29f ? by_ox[ox] : lo;
    const int c0 = std::max(0, 2 * ox - 1), c1 = std::min(kW - 1, 2 * ox);
    out.curve[c0] = std::max(out.curve[c0] == 0.0f ? lo : out.curve[c0], s);
    out.curve[c1] = std::max(out.curve[c1] == 0.0f ? lo : out.curve[c1], s);
  }
  if (!(best > 0.0f)) return SetNoEstimate(out, Reason::kNoMatch);
  // Prominence over the row of the best placement.
  float row_lo = best;
  float sorted[kOx];
  int n = 0;
  for (int ox = 0; ox < kOx; ++ox) {
    if (!done[ox][best_oy]) continue;
    row_lo = std::min(row_lo, score[ox][best_oy]);
    sorted[n++] = score[ox][best_oy];
  }
  std::nth_element(sorted, sorted + n / 2, sorted + n);
  const double prominence = best > row_lo ? (best - sorted[n / 2]) / (best - row_lo) : 0.0;
  if (prominence < options_.min_prominence) return SetNoEstimate(out, Reason::kFlatCurve);
  // Sub-pixel offset by a parabola through the neighbours (evaluated on demand).
  double ox_refined = best_ox;
  if (best_ox > 0 && best_ox < kOx - 1) {
    const double a = evaluate(best_ox - 1, best_oy), c = evaluate(best_ox + 1, best_oy);
    const double denom = a - 2.0 * best + c;
    if (denom < 0.0) ox_refined += std::clamp(0.5 * (a - c) / denom, -0.5, 0.5);
  }
  // Intersection of the corner lines = the fixed point of x → ox + (x − 0.5)/2.
  const double vx = 2.0 * ox_refined - 0.5;
  if (vx < -options_.vanishing_max_outside_px || vx > kW - 1 + options_.vanishing_max_outside_px)
    return SetNoEstimate(out, Reason::kDegenerateGeometry);
  out.column_px = vx;
  out.confidence = std::clamp(prominence, 0.0, 1.0);
  out.reason = Reason::kNone;
}

// ---------------------------------------------------------------------------------------------
// f5: median column of the brighter k-means cluster in the upper rows (§4.1.5). One-dimensional
// k-means with k = 2 on grey levels is a threshold iteration, done on the rows' histogram.
void BrightHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  const int rows = std::clamp(static_cast<int>(std::lround(options_.bright_rows_fraction * kH)), 1, kH);
  std::uint32_t hist[256] = {};
  const std::uint8_t* p = g.glance.pixels.data();
  for (int i = 0; i < rows * kW; ++i) ++hist[p[i]];
  // Prefix counts and sums for O(1) cluster means.
  std::uint32_t count[257] = {};
  std::uint64_t sum[257] = {};
  for (int k = 0; k < 256; ++k) {
    count[k + 1] = count[k] + hist[k];
    sum[k + 1] = sum[k] + static_cast<std::uint64_t>(hist[k]) * k;
  }
  int lo_level = 0, hi_level = 255;
  while (hist[lo_level] == 0) ++lo_level;
  while (hist[hi_level] == 0) --hi_level;
  if (lo_level == hi_level) return SetNoEstimate(out, Reason::kNoBrightCluster);
  // k-means (k = 2) on [first, 255]: returns the threshold (levels > t are bright) and centres.
  struct Split {
    int threshold = -1;
    double dark = 0.0, bright = 0.0;
  };
  auto kmeans = [&](int first) {
    Split sp;
    int lo = first, hi = 255;
    while (lo < 255 && hist[lo] == 0) ++lo;
    while (hi > 0 && hist[hi] == 0) --hi;
    if (lo >= hi) return sp;
    double c_dark = lo, c_bright = hi;
    for (int it = 0; it < options_.kmeans_iterations; ++it) {
      const int t = static_cast<int>(std::floor(0.5 * (c_dark + c_bright)));
      const std::uint32_t nd = count[t + 1] - count[first], nb = count[256] - count[t + 1];
      if (nd == 0 || nb == 0) break;
      const double new_dark = static_cast<double>(sum[t + 1] - sum[first]) / nd;
      const double new_bright = static_cast<double>(sum[256] - sum[t + 1]) / nb;
      sp = {t, new_dark, new_bright};
      if (new_dark == c_dark && new_bright == c_bright) break;
      c_dark = new_dark;
      c_bright = new_bright;
    }
    return sp;
  };
  // The paper's split; when its bright cluster is too large to be lights (a lit ceiling or
  // wall), split that cluster again (at most twice), keeping the brighter part each time.
  Split split = kmeans(lo_level);
  for (int level = 0; level < 2 && split.threshold >= 0; ++level) {
    const std::uint32_t nb = count[256] - count[split.threshold + 1];
    if (nb <= options_.bright_max_fraction * rows * kW) break;
    const Split inner = kmeans(split.threshold + 1);
    if (inner.threshold < 0) break;
    split = inner;
  }
  if (split.threshold < 0) return SetNoEstimate(out, Reason::kNoBrightCluster);
  const int threshold = split.threshold;
  const double c_dark = split.dark, c_bright = split.bright;
  const std::uint32_t n_bright = count[256] - count[threshold + 1];
  if (n_bright == 0 || c_bright - c_dark < options_.bright_min_separation ||
      n_bright > options_.bright_max_fraction * rows * kW)
    return SetNoEstimate(out, Reason::kNoBrightCluster);
  std::uint32_t per_column[kW] = {};
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < kW; ++u) per_column[u] += p[v * kW + u] > threshold;
  for (int u = 0; u < kW; ++u) out.curve[u] = static_cast<float>(per_column[u]);
  // Median of the bright pixels' columns, interpolated within the median column.
  const double half = 0.5 * n_bright;
  std::uint32_t cum = 0;
  double median = 0.0;
  for (int u = 0; u < kW; ++u) {
    if (cum + per_column[u] >= half && per_column[u] > 0) {
      median = u - 0.5 + (half - cum) / per_column[u];
      break;
    }
    cum += per_column[u];
  }
  out.column_px = std::clamp(median, 0.0, static_cast<double>(kW - 1));
  out.confidence = std::clamp((c_bright - c_dark) / 255.0, 0.0, 1.0);
  out.reason = Reason::kNone;
}

std::unique_ptr<HeadingMeasure> MakeHeadingMeasure(HeadingCue cue, const HeadingOptions& options,
                                                   std::optional<double> horizon_row) {
  switch (cue) {
    case HeadingCue::kEntropy: return std::make_unique<EntropyHeading>(options);
    case HeadingCue::kSymmetry: return std::make_unique<SymmetryHeading>(options);
    case HeadingCue::kPhase: return std::make_unique<PhaseHeading>(options, horizon_row);
    case HeadingCue::kVanishing: return std::make_unique<VanishingHeading>(options, horizon_row);
    case HeadingCue::kBright: return std::make_unique<BrightHeading>(options);
  }
  SQUINT_ENSURE(false, "unknown heading cue");
  return nullptr;
}

}  // namespace squint::corridor
