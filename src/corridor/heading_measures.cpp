// The five heading cues of paper §4.1 (f1 entropy, f2 symmetry, f3 phase, f4 vanishing point,
// f5 bright pixels), each scoring the glance's columns without allocating.
#include "squint/corridor/heading_measures.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <utility>
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

// Joint histograms of kBins × kBins small counts (row = first variable, column = second),
// `count` of them packed back to back. One helper clears them all.
template <int kBins, typename Count>
inline void ClearJointHistograms(Count* joint, int count) {
  std::memset(joint, 0, sizeof(Count) * kBins * kBins * static_cast<std::size_t>(count));
}

// Bit k set when counts[k] != 0, for kCount ≤ 64 counts of 8 or 16 bits.
template <int kCount, typename Count>
inline std::uint64_t OccupiedMask(const Count* counts) {
  static_assert(kCount <= 64);
  std::uint64_t mask = 0;
  int k = 0;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  if constexpr (sizeof(Count) == 1) {
    for (; k + 16 <= kCount; k += 16) {
      const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(counts + k));
      const unsigned empty = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(c, zero)));
      mask |= static_cast<std::uint64_t>(~empty & 0xFFFFu) << k;
    }
  } else {
    for (; k + 16 <= kCount; k += 16) {
      const __m128i lo = _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(counts + k)), zero);
      const __m128i hi = _mm_cmpeq_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(counts + k + 8)), zero);
      const unsigned empty = static_cast<unsigned>(_mm_movemask_epi8(_mm_packs_epi16(lo, hi)));
      mask |= static_cast<std::uint64_t>(~empty & 0xFFFFu) << k;
    }
  }
#endif
  for (; k < kCount; ++k) mask |= static_cast<std::uint64_t>(counts[k] != 0) << k;
  return mask;
}

// Row and column sums of a kBins × kBins joint histogram of n samples.
template <int kBins, typename Count>
inline void Marginals(const Count* joint, std::uint32_t n, std::uint32_t* row, std::uint32_t* col) {
  if constexpr (sizeof(Count) == 1 && kBins >= 8) {
    // 8-bit counts with n ≤ 255: eight cells per 64-bit word, added bytewise without carries
    // (no sum exceeds n); a row's sum is the top byte of word × 0x0101010101010101.
    if (n <= 255) {
      constexpr int kWords = kBins / 8;
      constexpr std::uint64_t kOnes = 0x0101010101010101ULL;
      std::uint64_t col_words[kWords] = {};
      for (int a = 0; a < kBins; ++a) {
        std::uint64_t row_word = 0;
        for (int w = 0; w < kWords; ++w) {
          std::uint64_t word;
          std::memcpy(&word, joint + a * kBins + 8 * w, 8);
          col_words[w] += word;
          row_word += word;
        }
        row[a] = static_cast<std::uint32_t>((row_word * kOnes) >> 56);
      }
      for (int b = 0; b < kBins; ++b) col[b] = static_cast<std::uint32_t>((col_words[b / 8] >> (8 * (b % 8))) & 0xFF);
      return;
    }
  }
  for (int a = 0; a < kBins; ++a) row[a] = col[a] = 0;
  for (int a = 0; a < kBins; ++a)
    for (int b = 0; b < kBins; ++b) {
      row[a] += joint[a * kBins + b];
      col[b] += joint[a * kBins + b];
    }
}

// Miller–Madow-corrected mutual information from a kBins × kBins joint histogram with
// N < kNLogNTableSize samples, using the n·log n table t: MI = (Σ t(n_ab) − Σ t(n_a) − Σ t(n_b) +
// t(N)) / N, minus the bias (B_a − 1)(B_b − 1) / 2N of the plug-in estimate (B = occupied bins).
// Only occupied cells are visited, in ascending index order: t(0) = 0 adds nothing, so the sum is
// bit-identical to the full scan.
template <int kBins, typename Count>
inline double CorrectedMutualInformation(const Count* joint, std::uint32_t n, const double* t) {
  constexpr int kCells = kBins * kBins;
  if (n == 0) return 0.0;
  std::uint32_t row[kBins], col[kBins];
  Marginals<kBins>(joint, n, row, col);
  double s = 0.0;
  for (int base = 0; base < kCells; base += 64) {
    constexpr int kChunk = kCells < 64 ? kCells : 64;
    for (std::uint64_t mask = OccupiedMask<kChunk>(joint + base); mask != 0; mask &= mask - 1)
      s += t[joint[base + std::countr_zero(mask)]];
  }
  int ra = 0, cb = 0;
  for (int a = 0; a < kBins; ++a) {
    s -= t[row[a]] + t[col[a]];
    ra += row[a] > 0;
    cb += col[a] > 0;
  }
  s += t[n];
  return s / n - (ra - 1) * (cb - 1) / (2.0 * n);
}

// Makes the compiler assume `array` was rewritten in memory, so that the cells computed with SIMD
// are then read back one by one as scalars (instead of extracting each lane from a register).
template <typename T>
inline void OpaqueToCompiler(T& array) {
#if defined(__GNUC__)
  asm volatile("" : "+m"(array));
#else
  (void)array;
#endif
}

// Calls kernel.template operator()<kBits>() for a bit depth 1..4 given at run time, so that the
// histogram kernels see their bin count as a constant.
template <typename Kernel>
inline void WithBits(int bits, Kernel&& kernel) {
  switch (bits) {
    case 1: return kernel.template operator()<1>();
    case 2: return kernel.template operator()<2>();
    case 3: return kernel.template operator()<3>();
    case 4: return kernel.template operator()<4>();
  }
  SQUINT_ENSURE(false, "histogram bit depth must be in [1, 4]");
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
  // log N for each slice width (narrower only at the borders), computed once per width.
  double log_n[kW + 1] = {};
  for (int x = 0; x < kW; ++x) {
    std::uint32_t hist[kMaxColumnBins] = {};
    const int a = std::max(0, x - r), b = std::min(kW - 1, x + r);
    for (int u = a; u <= b; ++u)
      for (int k = 0; k < bins; ++k) hist[k] += column_hist[u][k];
    const int width = b - a + 1;
    const auto n = static_cast<std::uint32_t>(width * kH);
    if (log_n[width] == 0.0) log_n[width] = std::log(static_cast<double>(n));
    out.curve[x] = static_cast<float>(EntropyFromCounts(hist, bins, n, log_n[width]));
  }
  SetFromPeak(detail::FindPeak(out.curve, 0, kW - 1, options_.border_px, options_.min_prominence), out);
}

// ---------------------------------------------------------------------------------------------
// f2: mirror symmetry by mutual information (§4.1.2, eq. 2). The axis at column x pairs pixel
// (x − d, v) with (x + d, v) for d = 1..D, D = min(half_width, x, 31 − x); axes with
// D < min_half_width are not scored. The bias correction keeps narrow windows (few pairs, whose
// plug-in MI is inflated) comparable with wide ones.
namespace {

// ++joint[x · kCells + cell[x]] for the columns x = kM..31 − kM, unrolled.
template <int kM, int kCells, typename Count>
void CountColumns(Count* joint, const std::uint8_t* cell) {
#pragma GCC unroll 32
  for (int x = kM; x <= kW - 1 - kM; ++x) ++joint[x * kCells + cell[x]];
}

template <int kCells, typename Count, std::size_t... kMs>
constexpr auto ColumnCounters(std::index_sequence<kMs...>) {
  return std::array<void (*)(Count*, const std::uint8_t*), sizeof...(kMs)>{
      &CountColumns<static_cast<int>(kMs), kCells, Count>...};
}

// Symmetry scores of the axes first..last = 31 − first. Every axis has its own joint histogram;
// a row's pairs at distance d are counted for all axes at once (no store-to-load chains between
// neighbouring increments, nothing to merge): the axes at distance d are x = m..31 − m with
// m = max(first, d), counted by an unrolled routine for that m. Count: uint8_t when no bin can
// exceed 255 (half_width · rows ≤ 255), else uint16_t.
template <int kBits, typename Count>
void SymmetryCurve(const std::uint8_t* level, int first, int half_width, bool significance,
                   std::array<float, kW>& curve) {
  constexpr int kBins = 1 << kBits, kCells = kBins * kBins;
  constexpr int kPad = 16;  // > the largest half width (15)
  static constexpr auto kCounters = ColumnCounters<kCells, Count>(std::make_index_sequence<kPad>());
  const int last = kW - 1 - first;
  alignas(16) Count joint[kW * kCells];
  ClearJointHistograms<kBins>(joint + first * kCells, last - first + 1);
  // The levels with kPad columns of zeros on either side, written before any row is read (a load
  // straddling fresh stores would stall on store forwarding).
  constexpr int kPaddedW = kW + 2 * kPad;
  alignas(16) std::uint8_t padded[kH * kPaddedW];
  for (int v = 0; v < kH; ++v) {
    std::memset(padded + v * kPaddedW, 0, kPad);
    std::memcpy(padded + v * kPaddedW + kPad, level + v * kW, kW);
    std::memset(padded + v * kPaddedW + kPad + kW, 0, kPad);
  }
  for (int v = 0; v < kH; ++v) {
    for (int d = 1; d <= half_width; ++d) {
      const std::uint8_t* left = padded + v * kPaddedW + kPad - d;
      const std::uint8_t* right = padded + v * kPaddedW + kPad + d;
      alignas(16) std::uint8_t cell[kW];
      for (int x = 0; x < kW; ++x) cell[x] = static_cast<std::uint8_t>((left[x] << kBits) + right[x]);
      OpaqueToCompiler(cell);
      kCounters[std::max(first, d)](joint, cell);
    }
  }
  const double* table = NLogNTable();
  for (int x = first; x <= last; ++x) {
    const int d_max = std::min({half_width, x, kW - 1 - x});
    const double mi =
        CorrectedMutualInformation<kBins>(joint + x * kCells, static_cast<std::uint32_t>(d_max * kH), table);
    curve[x] = static_cast<float>(significance ? mi * d_max / half_width : mi);
  }
}

}  // namespace

void SymmetryHeading::Measure(const PreparedGlance& g, HeadingMeasureResult& out) const {
  out.cue = Cue();
  out.curve.fill(0.0f);
  if (g.Uniform()) return SetNoEstimate(out, Reason::kUniformFrame);
  const int half_width = options_.symmetry_half_width_px;
  SQUINT_ENSURE(half_width >= 1 && half_width <= 15, "heading.symmetry_half_width_px must be in [1, 15]");
  // Axes with D < min_half_width are not scored (Validate: min ≤ half width ≤ 15, so some are).
  const int first = options_.symmetry_min_half_width_px, last = kW - 1 - first;
  if (last < first) return SetNoEstimate(out, Reason::kFlatCurve);
  const bool small_counts = half_width * kH <= 255;
  WithBits(options_.column_bits, [&]<int kBits>() {
    if (small_counts)
      SymmetryCurve<kBits, std::uint8_t>(g.column_level.data(), first, half_width, options_.symmetry_significance,
                                         out.curve);
    else
      SymmetryCurve<kBits, std::uint16_t>(g.column_level.data(), first, half_width, options_.symmetry_significance,
                                          out.curve);
  });
  float lowest = out.curve[first];
  for (int x = first; x <= last; ++x) lowest = std::min(lowest, out.curve[x]);
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
#if defined(__SSE2__)
    // Four pixels at a time with the same single-precision operations as the scalar loop below,
    // the votes then added in the same (column) order, so the sums are bit-identical. The whole
    // row is scanned: the border columns have gx = 0 and are skipped like any gx = 0 pixel.
    const __m128 lever4 = _mm_set1_ps(lever), tan4 = _mm_set1_ps(tan_vertical);
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    const __m128i min_mag2_4 = _mm_set1_epi32(min_mag2 - 1);
    for (int u0 = 0; u0 < kW; u0 += 4) {
      const __m128i gx16 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(gxr + u0));
      const __m128i gy16 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(gyr + u0));
      const __m128i pair = _mm_unpacklo_epi16(gx16, gy16);
      const __m128i m2 = _mm_madd_epi16(pair, pair);  // gx² + gy², exact
      const __m128i gx32 = _mm_srai_epi32(_mm_unpacklo_epi16(gx16, gx16), 16);
      const __m128i gy32 = _mm_srai_epi32(_mm_unpacklo_epi16(gy16, gy16), 16);
      const __m128i strong = _mm_andnot_si128(_mm_cmpeq_epi32(gx32, _mm_setzero_si128()),
                                              _mm_cmpgt_epi32(m2, min_mag2_4));
      const __m128 fgx = _mm_cvtepi32_ps(gx32), fgy = _mm_cvtepi32_ps(gy32);
      const __m128 vertical = _mm_cmplt_ps(_mm_and_ps(fgy, abs_mask), _mm_mul_ps(tan4, _mm_and_ps(fgx, abs_mask)));
      const __m128 col = _mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(u0), _mm_set_epi32(3, 2, 1, 0)));
      const __m128 x = _mm_sub_ps(col, _mm_div_ps(_mm_mul_ps(lever4, fgy), fgx));
      const __m128 inside = _mm_and_ps(_mm_cmpgt_ps(x, _mm_set1_ps(-1.0f)), _mm_cmplt_ps(x, _mm_set1_ps(static_cast<float>(kW))));
      const int mask = _mm_movemask_ps(_mm_andnot_ps(vertical, _mm_and_ps(inside, _mm_castsi128_ps(strong))));
      if (mask == 0) continue;
      alignas(16) float xs[4], ws[4];
      _mm_store_ps(xs, x);
      _mm_store_ps(ws, _mm_sqrt_ps(_mm_cvtepi32_ps(m2)));
      for (int bits = mask; bits != 0; bits &= bits - 1) {
        const int k = std::countr_zero(static_cast<unsigned>(bits));
        const float w = ws[k];
        const float xf = std::floor(xs[k]);
        const int i = static_cast<int>(xf);
        const float f = xs[k] - xf;
        votes[i + 1] += w * (1.0f - f);
        votes[i + 2] += w * f;
        total += w;
      }
    }
#else
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
#endif
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

namespace {

// Self-similarity scores of the half-size glance S placed at every horizontal offset and the rows
// oy_lo..oy_hi: score[oy][ox] = corrected MI of S and the glance window under it. `small` holds
// S's levels times kBins; `level` the glance's levels. All 17 offsets of a row are counted
// together (one histogram each; each S pixel's 17 increments fall in different histograms), in
// 8-bit counts (at most 16 × 12 = 192 per bin).
template <int kBits>
void VanishingScores(const std::uint8_t* small, const std::uint8_t* level, int oy_lo, int oy_hi,
                     float (*score)[kW - kW / 2 + 1]) {
  constexpr int kSw = kW / 2, kSh = kH / 2, kOx = kW - kSw + 1;
  constexpr int kBins = 1 << kBits, kCells = kBins * kBins;
  static_assert(kSw * kSh <= 255, "8-bit joint counts");
  alignas(16) std::uint8_t joint[kOx * kCells];
  const double* table = NLogNTable();
  for (int oy = oy_lo; oy <= oy_hi; ++oy) {
    ClearJointHistograms<kBins>(joint, kOx);
    for (int j = 0; j < kSh; ++j) {
      const std::uint8_t* a = small + j * kSw;
      const std::uint8_t* b = level + (oy + j) * kW;
      for (int i = 0; i < kSw; ++i) {
        std::uint8_t* h = joint + a[i];
        const std::uint8_t* bi = b + i;
        for (int ox = 0; ox < kOx; ++ox) ++h[ox * kCells + bi[ox]];
      }
    }
    for (int ox = 0; ox < kOx; ++ox)
      score[oy][ox] = static_cast<float>(CorrectedMutualInformation<kBins>(joint + ox * kCells, kSw * kSh, table));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// f4: vanishing point by self-similarity (§4.1.4). The half-size glance S (2×2 means) placed at
// offset (ox, oy) covers glance pixels ox..ox+15, oy..oy+11; S's pixel i has its centre at glance
// coordinate 2i + 0.5, so glance content at x appears at ox + (x − 0.5) / 2. The lines joining
// each glance corner to the corresponding corner of the placed S meet at the fixed point of that
// map, x = 2·ox − 0.5 (and y = 2·oy − 0.5): the vanishing point. Every ox is scored; oy is bounded near the horizon.
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
  float score[kH - kSh + 1][kOx];
  WithBits(options_.vanishing_bits, [&]<int kBits>() {
    VanishingScores<kBits>(small, g.vanishing_level.data(), oy_lo, oy_hi, score);
  });
  int best_ox = 0, best_oy = oy_lo;
  float best = -1e30f;
  // Every horizontal offset (the MI peak is about one offset wide, too sharp for a coarse grid)
  // over the bounded rows.
  for (int oy = oy_lo; oy <= oy_hi; ++oy) {
    for (int ox = 0; ox < kOx; ++ox) {
      const float s = score[oy][ox];
      if (s > best) best = s, best_ox = ox, best_oy = oy;
    }
  }
  // Curve: the best score of each column's candidate vanishing point, spread to both columns.
  std::array<float, kOx> by_ox{};
  by_ox.fill(-1e30f);
  for (int ox = 0; ox < kOx; ++ox)
    for (int oy = oy_lo; oy <= oy_hi; ++oy) by_ox[ox] = std::max(by_ox[ox], score[oy][ox]);
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
    row_lo = std::min(row_lo, score[best_oy][ox]);
    sorted[n++] = score[best_oy][ox];
  }
  std::nth_element(sorted, sorted + n / 2, sorted + n);
  const double prominence = best > row_lo ? (best - sorted[n / 2]) / (best - row_lo) : 0.0;
  if (prominence < options_.min_prominence) return SetNoEstimate(out, Reason::kFlatCurve);
  // Sub-pixel offset by a parabola through the neighbours.
  double ox_refined = best_ox;
  if (best_ox > 0 && best_ox < kOx - 1) {
    const double a = score[best_oy][best_ox - 1], c = score[best_oy][best_ox + 1];
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
