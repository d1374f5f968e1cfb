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
};

// Builds the table for a material; deterministic (fixed seeds per texture kind and name).
TextureTable MakeTexture(const Material& m, std::uint32_t seed);

}  // namespace squint::sim::detail
