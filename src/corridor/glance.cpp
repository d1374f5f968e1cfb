// Frame → 32×24 glance by point sampling (paper §4) or area averaging.
#include "squint/corridor/glance.hpp"

#include <algorithm>

#include "squint/core/error.hpp"

namespace squint::corridor {
void MakeGlance(const PixelView& frame, GlanceSampling sampling, Glance& out) {
  SQUINT_ENSURE(!frame.Empty(), "MakeGlance needs a non-empty frame");
  SQUINT_ENSURE(frame.channels == 1 || frame.channels == 3 || frame.channels == 4,
                "MakeGlance needs 1, 3 or 4 channels");
  const int w = frame.width, h = frame.height, ch = frame.channels;
  if (sampling == GlanceSampling::kPoint || w < kGlanceWidth || h < kGlanceHeight) {
    // The source pixel containing each glance cell's centre: floor((u + 0.5) · W / 32).
    std::array<int, kGlanceWidth> src_u{};
    for (int u = 0; u < kGlanceWidth; ++u) src_u[u] = std::min(w - 1, ((2 * u + 1) * w) / (2 * kGlanceWidth));
    for (int v = 0; v < kGlanceHeight; ++v) {
      const int sv = std::min(h - 1, ((2 * v + 1) * h) / (2 * kGlanceHeight));
      const std::uint8_t* row = frame.data + sv * frame.stride;
      std::uint8_t* dst = out.pixels.data() + v * kGlanceWidth;
      for (int u = 0; u < kGlanceWidth; ++u) dst[u] = GreyAt(row, src_u[u], ch);
    }
    return;
  }
  // Area: each glance pixel is the rounded mean of the source block [u·W/32, (u+1)·W/32).
  for (int v = 0; v < kGlanceHeight; ++v) {
    const int v0 = v * h / kGlanceHeight, v1 = (v + 1) * h / kGlanceHeight;
    for (int u = 0; u < kGlanceWidth; ++u) {
      const int u0 = u * w / kGlanceWidth, u1 = (u + 1) * w / kGlanceWidth;
      std::uint32_t sum = 0;
      for (int sv = v0; sv < v1; ++sv) {
        const std::uint8_t* row = frame.data + sv * frame.stride;
        for (int su = u0; su < u1; ++su) sum += GreyAt(row, su, ch);
      }
      const std::uint32_t n = static_cast<std::uint32_t>((v1 - v0) * (u1 - u0));
      out.At(u, v) = static_cast<std::uint8_t>((sum + n / 2) / n);
    }
  }
}

}  // namespace squint::corridor
