// The 32×24 grey "glance" every corridor measure works on (paper §4), made from any 8-bit
// grey or colour frame by point sampling (no smoothing) or, optionally, area averaging.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "squint/core/image_view.hpp"

namespace squint::corridor {

inline constexpr int kGlanceWidth = 32;
inline constexpr int kGlanceHeight = 24;
inline constexpr int kGlancePixels = kGlanceWidth * kGlanceHeight;

enum class GlanceSampling {
  kPoint,  // the paper: one source pixel per glance pixel (the one nearest the cell centre)
  kArea,   // the mean of the source pixels each glance pixel covers
};

// A fixed-size 32×24 grey image; no heap memory.
struct Glance {
  std::array<std::uint8_t, kGlancePixels> pixels{};

  std::uint8_t At(int u, int v) const { return pixels[static_cast<std::size_t>(v * kGlanceWidth + u)]; }
  std::uint8_t& At(int u, int v) { return pixels[static_cast<std::size_t>(v * kGlanceWidth + u)]; }
  GrayView View() const { return {pixels.data(), kGlanceWidth, kGlanceHeight, kGlanceWidth}; }
};

// An 8-bit interleaved image with 1 (grey), 3 (BGR) or 4 (BGRA) channels.
struct PixelView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // bytes between rows
  int channels = 1;

  static PixelView FromGray(const GrayView& g) { return {g.data, g.width, g.height, g.stride, 1}; }
  bool Empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

// The grey level of pixel u of a row of a 1-, 3- (BGR) or 4-channel (BGRA) frame: the pixel
// itself, or (29 B + 150 G + 77 R + 128) / 256. MakeGlance and MakeAreaImage read frames with it.
inline std::uint8_t GreyAt(const std::uint8_t* row, int u, int channels) {
  if (channels == 1) return row[u];
  const std::uint8_t* p = row + u * channels;
  return static_cast<std::uint8_t>((29u * p[0] + 150u * p[1] + 77u * p[2] + 128u) >> 8);
}

// Fills `out` from `frame`. Colour pixels become grey as (29·B + 150·G + 77·R) / 256 (BT.601).
// Frames smaller than the glance are point sampled (pixels repeat). Preconditions
// (SQUINT_ENSURE): a non-empty frame with 1, 3 or 4 channels.
void MakeGlance(const PixelView& frame, GlanceSampling sampling, Glance& out);
inline void MakeGlance(const GrayView& frame, GlanceSampling sampling, Glance& out) {
  MakeGlance(PixelView::FromGray(frame), sampling, out);
}

}  // namespace squint::corridor
