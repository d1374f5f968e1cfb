// The ceiling lights' line (explore/light_line.hpp) on constructed glances: a row of lights drawn
// by ray casting onto a plain ceiling at a known offset and direction must be read back.
#include "squint/explore/light_line.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "default_camera.hpp"
#include "squint/core/angles.hpp"

namespace squint::explore {
namespace {

// The default world's camera at the glance's 32×24.
CameraModel GlanceCamera() { return testing::DefaultWorldCamera(32, 24); }

// A 32×24 view of a ceiling `height` above the camera carrying rows of lights (0.3 m wide, 1.2 m
// long, every 3 m from 1 m ahead) at lateral offsets `rows_at` (left positive) from the robot,
// running at direction `dir_rad` (left positive); 4×4 samples per pixel. Below the horizon, floor.
// Only the lights' footprint on the ceiling plane is drawn (no walls): the geometry under test.
std::vector<std::uint8_t> Ceiling(const CameraModel& cam, double height, std::vector<double> rows_at, double dir_rad) {
  std::vector<std::uint8_t> img(static_cast<std::size_t>(cam.width * cam.height), 90);
  const double c = std::cos(dir_rad), s = std::sin(dir_rad);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      double sum = 0.0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const Eigen::Vector3d r = cam.PixelRayRobot({u - 0.375 + 0.25 * i, v - 0.375 + 0.25 * j});
          if (r.z() <= 1e-9) {
            sum += 90.0;
            continue;
          }
          const double x = height * r.x() / r.z(), y = height * r.y() / r.z();
          // Into the lights' frame: along their direction, across it.
          const double along = c * x + s * y, across = -s * x + c * y;
          bool lit = false;
          for (double at : rows_at) {
            const double k = std::fmod(along - 1.0, 3.0);
            if (along > 1.0 && k < 1.2 && std::abs(across - at) < 0.15) lit = true;
          }
          sum += lit ? 800.0 : 120.0;
        }
      // The lights far brighter than the ceiling, clipped by the exposure as rendered glances are:
      // a light covering a fifth of a pixel still shows well above the ceiling.
      img[static_cast<std::size_t>(v * cam.width + u)] = static_cast<std::uint8_t>(std::min(255L, std::lround(sum / 16.0)));
    }
  return img;
}

GrayView View(const std::vector<std::uint8_t>& img, const CameraModel& cam) {
  return GrayView{img.data(), cam.width, cam.height, cam.width};
}

TEST(LightLine, ReadsTheOffsetAndDirectionOfACentreRow) {
  const CameraModel cam = GlanceCamera();
  for (double offset : {-0.6, -0.25, 0.0, 0.3, 0.6})
    for (double dir_deg : {-8.0, 0.0, 5.0}) {
      SCOPED_TRACE(offset);
      SCOPED_TRACE(dir_deg);
      const auto img = Ceiling(cam, 2.2, {offset}, DegToRad(dir_deg));
      const LightLine l = FindLightLine(View(img, cam), cam);
      ASSERT_TRUE(l.valid);
      EXPECT_FALSE(l.side_rows);
      EXPECT_GE(l.rows, 3);
      // The robot stands -offset from the lights' line (metres at the true height) and the line
      // runs at dir_deg in the robot frame. The points are the rows' peak centroids at 32×24, so
      // the fit is good to about a tenth of a metre and a degree (over this grid: worst 0.155 m
      // and 0.83 deg, the two errors correlated through the fit); the signs are never wrong.
      EXPECT_NEAR(l.LateralM(2.2), -offset * std::cos(DegToRad(dir_deg)), 0.2);
      EXPECT_NEAR(RadToDeg(l.direction_rad), dir_deg, 1.0);
      if (std::abs(offset) >= 0.3) {
        EXPECT_LT(l.LateralM(2.2) * offset, 0.0);
      }
    }
}

TEST(LightLine, OffsetScalesWithTheAssumedHeight) {
  const CameraModel cam = GlanceCamera();
  const auto img = Ceiling(cam, 2.2, {0.5}, 0.0);
  const LightLine l = FindLightLine(View(img, cam), cam);
  ASSERT_TRUE(l.valid);
  EXPECT_NEAR(l.LateralM(4.4), 2.0 * l.LateralM(2.2), 1e-12);
  EXPECT_NEAR(l.offset_ratio, 0.5 / 2.2, 0.03);
}

TEST(LightLine, NoLineWithoutLightsOrOnTheWrongImage) {
  const CameraModel cam = GlanceCamera();
  const std::vector<std::uint8_t> plain(32 * 24, 120);
  EXPECT_FALSE(FindLightLine(View(plain, cam), cam).valid);
  // A view of another size than the camera's.
  const std::vector<std::uint8_t> small(16 * 12, 120);
  EXPECT_FALSE(FindLightLine(GrayView{small.data(), 16, 12, 16}, cam).valid);
  EXPECT_FALSE(FindLightLine(GrayView{}, cam).valid);
}

TEST(LightLine, TwoSideRowsAreNotTakenForACentreRow) {
  const CameraModel cam = GlanceCamera();
  const auto img = Ceiling(cam, 2.2, {-0.7, 0.7}, 0.0);
  const LightLine off = FindLightLine(View(img, cam), cam);
  EXPECT_FALSE(off.valid);
  // With side_rows, their midpoints give the centre line.
  LightLineOptions o;
  o.side_rows = true;
  const LightLine on = FindLightLine(View(img, cam), cam, o);
  ASSERT_TRUE(on.valid);
  EXPECT_TRUE(on.side_rows);
  EXPECT_NEAR(on.LateralM(2.2), 0.0, 0.06);
}

TEST(LightLine, ABrightStripeBesideAWallIsNoLight) {
  // A lit vertical stripe (a door frame) with wall grey on one side and ceiling on the other, in
  // every row above the horizon: its two sides differ, so it is no light peak.
  const CameraModel cam = GlanceCamera();
  std::vector<std::uint8_t> img(32 * 24, 120);
  for (int v = 0; v < 24; ++v) {
    for (int u = 0; u < 5; ++u) img[static_cast<std::size_t>(v * 32 + u)] = 175;  // wall
    img[static_cast<std::size_t>(v * 32 + 5)] = 230;                              // the frame
  }
  EXPECT_FALSE(FindLightLine(View(img, cam), cam).valid);
}

TEST(LightLine, OptionsAreValidated) {
  EXPECT_TRUE(LightLineOptions{}.Validate().empty());
  LightLineOptions o;
  o.min_rows = 2;
  EXPECT_NE(o.Validate().find("min_rows"), std::string::npos);
  o = LightLineOptions{};
  o.min_relative_contrast = 1.0;
  EXPECT_NE(o.Validate().find("min_relative_contrast"), std::string::npos);
  o = LightLineOptions{};
  o.nominal_height_m = 0.0;
  EXPECT_NE(o.Validate().find("nominal_height_m"), std::string::npos);
}

}  // namespace
}  // namespace squint::explore
