// Per-glance shared quantities: whole-glance histogram and entropy, quantised levels, Sobel.
#include "squint/corridor/prepared_glance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <cstring>

#include "squint/corridor/information.hpp"

namespace squint::corridor {

namespace {

// Counts grey levels >> shift into four interleaved partial histograms (stride `bins`): an
// increment that follows one to the same counter waits for its store, and neighbouring glance
// pixels often share a bin. A compile-time shift keeps the loop to loads and increments.
template <int kShift>
void CountLevels(const std::uint8_t* p, int bins, std::uint16_t* part) {
  std::uint16_t* p0 = part;
  std::uint16_t* p1 = p0 + bins;
  std::uint16_t* p2 = p1 + bins;
  std::uint16_t* p3 = p2 + bins;
  for (int i = 0; i < kGlancePixels; i += 4) {
    ++p0[p[i] >> kShift];
    ++p1[p[i + 1] >> kShift];
    ++p2[p[i + 2] >> kShift];
    ++p3[p[i + 3] >> kShift];
  }
}

template <int... kShifts>
void CountLevelsDispatch(int shift, const std::uint8_t* p, int bins, std::uint16_t* part,
                         std::integer_sequence<int, kShifts...>) {
  ((shift == kShifts ? (CountLevels<kShifts>(p, bins, part), true) : false) || ...);
}

}  // namespace

void ComputeHistogramAndEntropy(const Glance& glance, int image_bits, PreparedGlance& out) {
  out.glance = glance;
  const int shift = 8 - image_bits;
  out.image_bins = 1 << image_bits;
  const int bins = out.image_bins;
  // 16-bit counts (at most 768), packed with stride `bins` so that only the used part is cleared.
  static_assert(kGlancePixels <= 65535 && kGlancePixels % 4 == 0);
  std::uint16_t part[4 * kMaxImageBins];
  std::memset(part, 0, sizeof(std::uint16_t) * 4 * static_cast<std::size_t>(bins));
  const std::uint8_t* p = glance.pixels.data();
  CountLevelsDispatch(shift, p, bins, part, std::make_integer_sequence<int, 8>{});
  std::uint8_t lo = 255, hi = 0;
  for (int i = 0; i < kGlancePixels; ++i) {
    lo = std::min(lo, p[i]);
    hi = std::max(hi, p[i]);
  }
  const std::uint16_t* p0 = part;
  const std::uint16_t* p1 = p0 + bins;
  const std::uint16_t* p2 = p1 + bins;
  const std::uint16_t* p3 = p2 + bins;
  for (int b = 0; b < bins; ++b) out.histogram[b] = static_cast<std::uint32_t>(p0[b] + p1[b] + p2[b] + p3[b]);
  out.min_level = lo;
  out.max_level = hi;
  // Entropy (nats) = log N − Σ c log c / N, the sum in four chains (a single chain of dependent
  // additions is latency-bound).
  const double* nlogn = NLogNTable();
  static_assert(kGlancePixels < kNLogNTableSize);
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  int b = 0;
  for (; b + 4 <= bins; b += 4) {
    s[0] += nlogn[out.histogram[b]];
    s[1] += nlogn[out.histogram[b + 1]];
    s[2] += nlogn[out.histogram[b + 2]];
    s[3] += nlogn[out.histogram[b + 3]];
  }
  for (; b < bins; ++b) s[0] += nlogn[out.histogram[b]];
  static const double kLogPixels = std::log(static_cast<double>(kGlancePixels));
  const double h = kLogPixels - ((s[0] + s[1]) + (s[2] + s[3])) / kGlancePixels;
  out.entropy = h > 0.0 ? h : 0.0;  // rounding can give -1e-16 for a single full bin
  out.valid = true;
}

void PrepareMeasures(int column_bits, int vanishing_bits, PreparedGlance& out) {
  const std::uint8_t* p = out.glance.pixels.data();
  const int cs = 8 - column_bits, vs = 8 - vanishing_bits;
  for (int i = 0; i < kGlancePixels; ++i) {
    out.column_level[i] = static_cast<std::uint8_t>(p[i] >> cs);
    out.vanishing_level[i] = static_cast<std::uint8_t>(p[i] >> vs);
  }
  constexpr int w = kGlanceWidth;
  out.grad_x.fill(0);
  out.grad_y.fill(0);
  for (int v = 1; v < kGlanceHeight - 1; ++v) {
    const std::uint8_t* a = p + (v - 1) * w;
    const std::uint8_t* b = p + v * w;
    const std::uint8_t* c = p + (v + 1) * w;
    for (int u = 1; u < w - 1; ++u) {
      const int gx = (a[u + 1] + 2 * b[u + 1] + c[u + 1]) - (a[u - 1] + 2 * b[u - 1] + c[u - 1]);
      const int gy = (c[u - 1] + 2 * c[u] + c[u + 1]) - (a[u - 1] + 2 * a[u] + a[u + 1]);
      out.grad_x[v * w + u] = static_cast<std::int16_t>(gx);
      out.grad_y[v * w + u] = static_cast<std::int16_t>(gy);
    }
  }
}

}  // namespace squint::corridor
