// Procedural textures as periodic 8-bit lookup tables (internal to the renderer): each table
// holds kTexReps × kTexReps periods of its pattern at kTexSize² texels, mean value about 128.
#pragma once

#include <array>
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

  // Mean factor (texel * gain) over the texels meeting the box [u0, u1] × [v0, v1] (metres,
  // u0 <= u1, v0 <= v1), the table repeated periodically; a box wider than the table is
  // averaged over one table width (the pattern's mean).
  float BoxMean(double u0, double u1, double v0, double v1) const;
};

// Builds the table for a material; deterministic (fixed seeds per texture kind and name).
TextureTable MakeTexture(const Material& m, std::uint32_t seed);

}  // namespace squint::sim::detail
