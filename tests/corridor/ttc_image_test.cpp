// Time to contact's own finer image (DistanceOptions::ttc_glance_scale): exact area averaging,
// the scale search on an image larger than the glance, and the Perceiver tracking an approach
// on it while its default options stay on the glance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "squint/corridor/distance_measures.hpp"
#include "squint/corridor/perceiver.hpp"

namespace squint::corridor {
namespace {

TEST(MakeAreaImage, KnownAnswers) {
  // A 160×120 frame whose pixel is (u + v) mod 100.
  std::vector<std::uint8_t> frame(160 * 120);
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u) frame[v * 160 + u] = static_cast<std::uint8_t>((u + v) % 100);
  const PixelView view{frame.data(), 160, 120, 160, 1};
  // 2× (80×60): each pixel is the mean of a 2×2 block.
  std::vector<std::uint8_t> out(80 * 60);
  MakeAreaImage(view, 80, 60, out.data());
  for (int v = 0; v < 60; ++v)
    for (int u = 0; u < 80; ++u) {
      double sum = 0.0;
      for (int dv = 0; dv < 2; ++dv)
        for (int du = 0; du < 2; ++du) sum += frame[(2 * v + dv) * 160 + 2 * u + du];
      ASSERT_EQ(out[v * 80 + u], static_cast<std::uint8_t>(std::floor(sum / 4.0 + 0.5))) << u << "," << v;
    }
  // 5× (32×24) equals the glance's area averaging.
  Glance glance;
  MakeGlance(view, GlanceSampling::kArea, glance);
  std::vector<std::uint8_t> g(kGlancePixels);
  MakeAreaImage(view, kGlanceWidth, kGlanceHeight, g.data());
  EXPECT_TRUE(std::equal(g.begin(), g.end(), glance.pixels.begin()));
  // 2.5× (64×48): partial source pixels weigh by their covered fraction. Pixel (0, 0) covers
  // source columns 0, 1 and half of 2, rows likewise.
  std::vector<std::uint8_t> fine(64 * 48);
  MakeAreaImage(view, 64, 48, fine.data());
  double sum = 0.0;
  const double w[3] = {1.0, 1.0, 0.5};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) sum += w[r] * w[c] * frame[r * 160 + c];
  EXPECT_EQ(fine[0], static_cast<std::uint8_t>(std::floor(sum / 6.25 + 0.5)));
  // A uniform colour frame stays uniform, grey as MakeGlance's.
  std::vector<std::uint8_t> bgr(160 * 120 * 3);
  for (std::size_t i = 0; i < bgr.size(); i += 3) bgr[i] = 10, bgr[i + 1] = 200, bgr[i + 2] = 90;
  MakeAreaImage(PixelView{bgr.data(), 160, 120, 160 * 3, 3}, 64, 48, fine.data());
  const auto grey = static_cast<std::uint8_t>((29u * 10 + 150u * 200 + 77u * 90 + 128u) >> 8);
  EXPECT_TRUE(std::all_of(fine.begin(), fine.end(), [&](std::uint8_t p) { return p == grey; }));
}

// A smooth pattern on a plane, magnified by `scale` about the centre of a w×h image.
std::vector<std::uint8_t> Pattern(int w, int h, double scale) {
  std::vector<std::uint8_t> img(static_cast<std::size_t>(w * h));
  const double cx = (w - 1) / 2.0, cy = (h - 1) / 2.0, k = 32.0 / w;  // the same angles at any size
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double x = (u - cx) * k / scale, y = (v - cy) * k / scale;
      const double value = 128.0 + 50.0 * std::sin(0.31 * x + 0.17 * y) + 40.0 * std::cos(0.23 * y - 0.27 * x + 0.5);
      img[v * w + u] = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  return img;
}

TEST(ExpansionScale, RecoversAKnownMagnificationOnAFinerImage) {
  for (const double k : {1.02, 1.05, 1.1}) {
    const auto a = Pattern(64, 48, 1.0), b = Pattern(64, 48, k);
    const TtcImage ia{a.data(), 64, 48}, ib{b.data(), 64, 48};
    const auto m = ExpansionScale(ia, ib, 31.5, 23.5, 64, 48, 1.5);
    ASSERT_TRUE(m.has_value()) << k;
    EXPECT_NEAR(m->scale, k, 0.004) << k;
    const auto cells = CellExpansionScales(ia, ib, 31.5, 23.5, 30, 22, 1.5, m->scale, 12.0, 2.0, 0.8);
    ASSERT_TRUE(cells.has_value());
    EXPECT_GE(cells->count, 8);
    for (int i = 0; i < cells->count; ++i) EXPECT_NEAR(cells->scale[i], k, 0.01) << k << " cell " << i;
  }
}

TEST(TimeToContactDistance, FinerImageScalesTheGeometry) {
  // The same plane at 32×24, 64×48 and 96×72, the expansion centre, focal length, window and
  // cells given in glance pixels: every size reads s / (σ − 1) (the window alone within 1.5 %,
  // the median of the 8 nearest cells of this smooth pattern within 4 %). A centre or window
  // left unscaled would put the expansion centre far from the pattern's.
  const double k = 1.04, s = 0.4;  // 0.4 m driven, d = 10 m
  for (const double cell_px : {0.0, 6.0}) {
    DistanceOptions o;
    o.ttc_cell_px = cell_px;
    o.ttc_cell_nearest = 8;
    const TimeToContactDistance ttc(o, 15.5, 11.5, 30.0, 0.7);
    for (const int w : {32, 64, 96}) {
      const int h = w * 3 / 4;
      const auto a = Pattern(w, h, 1.0), b = Pattern(w, h, k);
      DistanceMeasureResult r;
      ttc.MeasureScale(TtcImage{a.data(), w, h}, TtcImage{b.data(), w, h}, 4, s, 10.0, r);
      ASSERT_TRUE(r.dist_m.has_value()) << w << ": " << ReasonText(r.reason);
      EXPECT_NEAR(*r.dist_m, s / (k - 1.0), (cell_px > 0.0 ? 0.04 : 0.015) * s / (k - 1.0)) << w << " " << cell_px;
    }
  }
  // Images of different sizes are not compared.
  const TimeToContactDistance ttc(DistanceOptions{}, 15.5, 11.5, 30.0, 0.7);
  const auto a = Pattern(32, 24, 1.0), b = Pattern(64, 48, k);
  DistanceMeasureResult r;
  ttc.MeasureScale(TtcImage{a.data(), 32, 24}, TtcImage{b.data(), 64, 48}, 4, s, 10.0, r);
  EXPECT_FALSE(r.dist_m.has_value());
}

// A 160×120 frame of the plane `z` metres ahead (it started z0 away), magnified about the
// frame's centre.
std::vector<std::uint8_t> PlaneFrame(double z, double z0 = 12.0) {
  std::vector<std::uint8_t> img(160 * 120);
  const double scale = z0 / z;
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u) {
      const double x = (u - 79.5) / 5.0 / scale, y = (v - 59.5) / 5.0 / scale;
      const double value = 128.0 + 50.0 * std::sin(0.31 * x + 0.17 * y) + 40.0 * std::cos(0.23 * y - 0.27 * x + 0.5);
      img[v * 160 + u] = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    }
  return img;
}

TEST(PerceiverDistance, FinerTimeToContactImageTracksAnApproach) {
  for (const double scale : {1.0, 2.0, 2.5}) {
    CorridorOptions o;
    o.gate.enabled = false;
    for (auto& c : o.heading.cues) c.enabled = false;
    o.distance.enabled = {true, false, false};
    o.distance.ttc_glance_scale = scale;
    Perceiver perceiver(o, std::nullopt);
    const double step = 0.05;
    double sum2 = 0.0;
    int n = 0;
    for (int i = 0; i <= 60; ++i) {
      const double z = 12.0 - step * i;
      const auto frame = PlaneFrame(z);
      const PerceptionResult r = perceiver.Process(GrayView{frame.data(), 160, 120, 160},
                                                   i == 0 ? std::nullopt : std::optional(step), 0.1);
      if (i < 16) continue;  // warm-up and the median window
      const double e = r.dist_end_m ? *r.dist_end_m - z : z;
      sum2 += e * e;
      ++n;
    }
    EXPECT_LT(std::sqrt(sum2 / n), 0.05 * 10.0) << "scale " << scale;
  }
}

TEST(CorridorOptions, TtcGlanceScaleIsValidated) {
  CorridorOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.distance.ttc_glance_scale = 0.5;
  EXPECT_NE(o.Validate().find("ttc_glance_scale"), std::string::npos);
  o.distance.ttc_glance_scale = 4.5;
  EXPECT_NE(o.Validate().find("ttc_glance_scale"), std::string::npos);
  o.distance.ttc_glance_scale = 2.0;
  EXPECT_TRUE(o.Validate().empty());
  o.distance.ttc_scale_search = false;
  EXPECT_NE(o.Validate().find("ttc_scale_search"), std::string::npos);
}

}  // namespace
}  // namespace squint::corridor
