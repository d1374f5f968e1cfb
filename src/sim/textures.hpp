// Procedural textures as periodic 8-bit lookup tables (internal to the renderer): each table
// holds kTexReps × kTexReps periods of its pattern at kTexSize² texels, mean value about 128.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "squint/sim/world.hpp"

namespace squint::sim::detail {

inline constexpr int kTexSize = 128;   // texels per table side (power of two; 16 KB tables stay in cache)
inline constexpr int kTexReps = 2;     // pattern periods per table side

struct TextureTable {
  std::vector<std::uint8_t> texels;  // kTexSize * kTexSize, row-major (v rows, u columns)
  float inv_texel_m = 1.0f;          // texels per metre: kTexSize / (kTexReps * scale_m)
  float gain = 1.0f / 128.0f;        // texel -> multiplicative factor
  // Summed-area table of one period of the table: sat[y * (kTexSize + 1) + x] is the sum of
  // texels [0, x) × [0, y); with the periodic extension it gives box means in O(1).
  std::vector<std::uint32_t> sat;
  // The summed-area table's last column (whole rows' sums, sat[y * (kTexSize + 1) + kTexSize]),
  // contiguous: a box that wraps around the table reads two of them, which then share a cache line.
  std::vector<std::uint32_t> sat_last_col;

  // Mean factor (texel * gain) over the texels meeting the box [u0, u1] × [v0, v1] (metres,
  // u0 <= u1, v0 <= v1), the table repeated periodically; a box wider than the table is
  // averaged over one table width (the pattern's mean).
  [[gnu::always_inline]] float BoxMean(double u0, double u1, double v0, double v1) const;
};

// Builds the table for a material; deterministic (fixed seeds per texture kind and name).
TextureTable MakeTexture(const Material& m, std::uint32_t seed);

// std::floor for the texel coordinates (|x| far below 2^62), without a libm call.
inline std::int64_t FloorToInt(double x) {
  const auto i = static_cast<std::int64_t>(x);  // truncates toward zero
  return i - (static_cast<double>(i) > x);
}

// Inline: the renderer calls it once per adaptively shaded region.
[[gnu::always_inline]] inline float TextureTable::BoxMean(double u0, double u1, double v0, double v1) const {
  constexpr int kS = kTexSize + 1;
  // Texel columns [x0, x1) and rows [y0, y1) meeting the box, at most one table wide.
  const std::int64_t x0 = FloorToInt(u0 * inv_texel_m);
  const std::int64_t y0 = FloorToInt(v0 * inv_texel_m);
  const std::int64_t x1 = std::min<std::int64_t>(FloorToInt(u1 * inv_texel_m) + 1, x0 + kTexSize);
  const std::int64_t y1 = std::min<std::int64_t>(FloorToInt(v1 * inv_texel_m) + 1, y0 + kTexSize);
  // The periodic extension's prefix sum is S2(x, y) = qx qy T + qx C(ry) + qy R(rx) + S(rx, ry)
  // with q = floor(x / kTexSize), r = x mod kTexSize, T the table total, C and R the sums of
  // whole rows and columns; the box sum S2(x1,y1) - S2(x0,y1) - S2(x1,y0) + S2(x0,y0) groups into:
  static_assert(kTexSize == 128, "the division by kTexSize shifts by 7");
  const std::int64_t qx0 = x0 >> 7, qx1 = x1 >> 7, qy0 = y0 >> 7, qy1 = y1 >> 7;
  const std::int64_t rx0 = x0 & (kTexSize - 1), rx1 = x1 & (kTexSize - 1), ry0 = y0 & (kTexSize - 1), ry1 = y1 & (kTexSize - 1);
  const auto at = [&](std::int64_t i, std::int64_t j) { return static_cast<std::int64_t>(sat[j * kS + i]); };
  const double area = static_cast<double>((x1 - x0) * (y1 - y0));
  // Exact integer sums, all terms taken (those whose factor is zero add nothing): no branch on
  // whether the box wraps (31% of the boxes do, at random).
  const std::int64_t dqx = qx1 - qx0, dqy = qy1 - qy0;
  const std::uint32_t* col = sat_last_col.data();
  std::int64_t sum = at(rx1, ry1) - at(rx0, ry1) - at(rx1, ry0) + at(rx0, ry0);
  sum += dqx * (static_cast<std::int64_t>(col[ry1]) - col[ry0]);
  sum += dqy * (at(rx1, kTexSize) - at(rx0, kTexSize));
  sum += dqx * dqy * static_cast<std::int64_t>(col[kTexSize]);
  return static_cast<float>(static_cast<double>(sum) / area) * gain;
}

}  // namespace squint::sim::detail
