// Procedural texture generation: tiles, speckle, carpet, brick, panels, posters, windows, glass.
#include "textures.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace squint::sim::detail {
namespace {

// Smooth value noise with the given number of cells per table side (periodic).
std::vector<float> ValueNoise(int cells, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> lattice(static_cast<std::size_t>(cells) * cells);
  for (float& v : lattice) v = u(rng);
  std::vector<float> out(static_cast<std::size_t>(kTexSize) * kTexSize);
  for (int y = 0; y < kTexSize; ++y)
    for (int x = 0; x < kTexSize; ++x) {
      const float fx = static_cast<float>(x) * cells / kTexSize, fy = static_cast<float>(y) * cells / kTexSize;
      const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
      const float tx = fx - x0, ty = fy - y0;
      const float sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
      auto at = [&](int i, int j) { return lattice[(j % cells) * cells + (i % cells)]; };
      const float a = at(x0, y0) + sx * (at(x0 + 1, y0) - at(x0, y0));
      const float b = at(x0, y0 + 1) + sx * (at(x0 + 1, y0 + 1) - at(x0, y0 + 1));
      out[y * kTexSize + x] = a + sy * (b - a);
    }
  return out;
}

}  // namespace

TextureTable MakeTexture(const Material& m, std::uint32_t seed) {
  TextureTable t;
  t.texels.assign(static_cast<std::size_t>(kTexSize) * kTexSize, 128);
  t.inv_texel_m = static_cast<float>(kTexSize / (kTexReps * m.scale_m));
  std::mt19937 rng(seed * 2654435761u + static_cast<std::uint32_t>(m.texture) * 97u + 13u);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  const float c = static_cast<float>(m.contrast);
  const int period = kTexSize / kTexReps;  // texels per pattern period
  std::vector<float> f(t.texels.size(), 1.0f);
  const auto fine = ValueNoise(32, rng);
  const auto coarse = ValueNoise(4, rng);
  switch (m.texture) {
    case Texture::kPlain:
      for (std::size_t i = 0; i < f.size(); ++i) f[i] = 1.0f + 0.15f * c * fine[i] + 0.02f * coarse[i];
      break;
    case Texture::kTiles: {
      // Tiles of one period with grout lines; each tile slightly different.
      std::vector<float> tile_shade(kTexReps * kTexReps);
      for (float& s : tile_shade) s = 0.35f * c * (uni(rng) - 0.5f);
      const int grout = std::max(1, period / 28);
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) {
          const bool line = (x % period) < grout || (y % period) < grout;
          const float shade = tile_shade[(y / period) * kTexReps + x / period];
          f[y * kTexSize + x] = line ? 1.0f - c : 1.0f + shade + 0.1f * c * fine[y * kTexSize + x];
        }
      break;
    }
    case Texture::kSpeckle:
      for (std::size_t i = 0; i < f.size(); ++i) {
        float v = 1.0f + 0.15f * c * coarse[i];
        const float r = uni(rng);
        if (r < 0.06f) v -= c * (0.5f + 0.5f * uni(rng));
        else if (r < 0.10f) v += 0.6f * c * uni(rng);
        f[i] = v;
      }
      break;
    case Texture::kCarpet:
      for (std::size_t i = 0; i < f.size(); ++i) f[i] = 1.0f + 0.5f * c * fine[i] + 0.3f * c * gauss(rng) + 0.2f * c * coarse[i];
      break;
    case Texture::kBrick: {
      const int bh = std::max(2, period * 2 / 5);  // brick height: 0.4 of its length
      const int mortar = std::max(1, period / 20);
      std::vector<float> shade(4096);
      for (float& s : shade) s = 0.3f * c * (uni(rng) - 0.5f);
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) {
          const int row = y / bh;
          const int xs = (x + (row % 2) * period / 2) % kTexSize;
          const bool line = (y % bh) < mortar || (xs % period) < mortar;
          const float s = shade[(row * 17 + xs / period) % 4096];
          f[y * kTexSize + x] = line ? 1.0f + 0.6f * c : 1.0f - 0.2f * c + s + 0.15f * c * fine[y * kTexSize + x];
        }
      break;
    }
    case Texture::kPanels:
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) {
          const int px = x % period;
          const float seam = px < std::max(1, period / 40) ? -c : (px < period / 20 + 2 ? 0.3f * c : 0.0f);
          f[y * kTexSize + x] = 1.0f + seam + 0.1f * c * static_cast<float>(px) / period + 0.05f * c * fine[y * kTexSize + x];
        }
      break;
    case Texture::kPoster: {
      // Blocks and text-like lines on a light background; the table's first period is one poster.
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) f[y * kTexSize + x] = 1.0f + 0.3f * c;
      for (int k = 0; k < 10; ++k) {
        const int x0 = static_cast<int>(uni(rng) * period * 0.8f), y0 = static_cast<int>(uni(rng) * period * 0.8f);
        const int w = 4 + static_cast<int>(uni(rng) * period * 0.5f), h = 2 + static_cast<int>(uni(rng) * period * (k < 4 ? 0.4f : 0.06f));
        const float v = 1.0f + c * (uni(rng) * 1.6f - 1.0f);
        for (int y = y0; y < std::min(period, y0 + h); ++y)
          for (int x = x0; x < std::min(period, x0 + w); ++x)
            for (int ry = 0; ry < kTexReps; ++ry)
              for (int rx = 0; rx < kTexReps; ++rx) f[(y + ry * period) * kTexSize + x + rx * period] = v;
      }
      break;
    }
    case Texture::kWindow:
      // Panes (bright, cloudy) between dark mullions.
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) {
          const bool frame = (x % period) < period / 12 || (y % (period / 2)) < period / 16;
          f[y * kTexSize + x] = frame ? 1.0f - c : 1.0f + 0.5f * c * coarse[y * kTexSize + x];
        }
      break;
    case Texture::kGlass:
      for (int y = 0; y < kTexSize; ++y)
        for (int x = 0; x < kTexSize; ++x) {
          const bool frame = (x % period) < period / 16;
          f[y * kTexSize + x] = frame ? 1.0f - c : 1.0f + 0.25f * c * coarse[y * kTexSize + x] + 0.1f * c * (float(y % period) / period);
        }
      break;
  }
  for (std::size_t i = 0; i < f.size(); ++i) t.texels[i] = static_cast<std::uint8_t>(std::clamp(f[i] * 128.0f, 0.0f, 255.0f));
  constexpr int kS = kTexSize + 1;
  t.sat.assign(static_cast<std::size_t>(kS) * kS, 0);
  for (int y = 0; y < kTexSize; ++y) {
    std::uint32_t row = 0;
    for (int x = 0; x < kTexSize; ++x) {
      row += t.texels[static_cast<std::size_t>(y) * kTexSize + x];
      t.sat[static_cast<std::size_t>(y + 1) * kS + x + 1] = t.sat[static_cast<std::size_t>(y) * kS + x + 1] + row;
    }
  }
  t.sat_last_col.resize(kS);
  for (int y = 0; y < kS; ++y) t.sat_last_col[y] = t.sat[static_cast<std::size_t>(y) * kS + kTexSize];
  return t;
}

}  // namespace squint::sim::detail
