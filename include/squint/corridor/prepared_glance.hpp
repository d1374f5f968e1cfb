// A glance with the per-glance quantities every measure shares (quantised grey levels, Sobel
// gradients, the whole-glance histogram and entropy), computed once per frame without allocation.
#pragma once

#include <array>
#include <cstdint>

#include "squint/corridor/glance.hpp"

namespace squint::corridor {

inline constexpr int kMaxImageBins = 256;

struct PreparedGlance {
  Glance glance;
  // Grey levels >> (8 - column_bits) for column histograms, and >> (8 - vanishing_bits).
  std::array<std::uint8_t, kGlancePixels> column_level{};
  std::array<std::uint8_t, kGlancePixels> vanishing_level{};
  // Sobel derivatives (zero on the one-pixel border), in grey levels × 8.
  std::array<std::int16_t, kGlancePixels> grad_x{};
  std::array<std::int16_t, kGlancePixels> grad_y{};
  // Whole-glance histogram at 2^image_bits bins and its entropy (nats).
  std::array<std::uint32_t, kMaxImageBins> histogram{};
  int image_bins = 64;
  double entropy = 0.0;
  std::uint8_t min_level = 0;
  std::uint8_t max_level = 0;
  bool valid = false;

  bool Uniform() const { return min_level == max_level; }
};

// Whole-glance histogram and entropy only (what the rapid-perception gate needs).
void ComputeHistogramAndEntropy(const Glance& glance, int image_bits, PreparedGlance& out);
// Everything else (quantised levels, gradients); call after ComputeHistogramAndEntropy.
void PrepareMeasures(int column_bits, int vanishing_bits, PreparedGlance& out);

}  // namespace squint::corridor
