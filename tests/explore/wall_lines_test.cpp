// The walls' base lines (explore/wall_lines.hpp) on constructed frames: a textured floor between
// two smooth walls, drawn by the camera model, at known directions and offsets.
#include "squint/explore/wall_lines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "squint/core/angles.hpp"

namespace squint::explore {
namespace {

CameraModel Camera128() {
  CameraModel c;
  c.width = 128;
  c.height = 96;
  c.fx = c.fy = 0.5 * 128 / std::tan(DegToRad(55.0) / 2.0);
  c.cx = 63.5;
  c.cy = 47.5;
  c.height_m = 0.55;
  c.pitch_deg = -2.0;
  return c;
}

// A corridor whose walls run along `direction_deg` in the robot frame (left positive), the left
// wall `left_m` and the right wall `right_m` from the robot (distances along the walls' normal).
// The floor between them carries a speckle of 4 cm cells (or, without `textured_floor`, the
// walls' own grey); the walls are a smooth grey with a gentle vertical shading; the ceiling and
// what lies beyond max_floor_m (or, along the walls, beyond end_along_m: an end wall) are plain.
std::vector<std::uint8_t> Draw(const CameraModel& cam, double direction_deg, double left_m, double right_m,
                               double max_floor_m = 30.0, bool textured_floor = true, double end_along_m = 1e9) {
  std::vector<std::uint8_t> img(static_cast<std::size_t>(cam.width * cam.height));
  const double t = DegToRad(direction_deg);
  const Eigen::Vector2d along(std::cos(t), std::sin(t)), normal(-std::sin(t), std::cos(t));
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      std::uint8_t g = static_cast<std::uint8_t>(120 + v / 8);  // wall (or ceiling)
      if (const auto p = cam.FloorPoint({static_cast<double>(u), static_cast<double>(v)})) {
        const double across = normal.dot(*p);
        if (across < left_m && across > -right_m && p->norm() < max_floor_m && along.dot(*p) < end_along_m) {
          if (textured_floor) {
            const auto a = static_cast<std::int64_t>(std::floor(along.dot(*p) / 0.04));
            const auto b = static_cast<std::int64_t>(std::floor(across / 0.04));
            std::uint64_t h = static_cast<std::uint64_t>(a * 73856093LL) ^ static_cast<std::uint64_t>(b * 19349663LL);
            h ^= h >> 13;
            h *= 0x9E3779B97F4A7C15ULL;
            h ^= h >> 29;
            g = static_cast<std::uint8_t>(90 + static_cast<int>(h % 60));
          }
        }
      }
      img[static_cast<std::size_t>(v * cam.width + u)] = g;
    }
  }
  return img;
}

GrayView View(const CameraModel& cam, const std::vector<std::uint8_t>& img) {
  return {img.data(), cam.width, cam.height, cam.width};
}

TEST(WallLines, TwoWallsGiveTheirDirectionAndOffsets) {
  const CameraModel cam = Camera128();
  for (const double dir_deg : {-25.0, -10.0, 0.0, 7.0, 20.0}) {
    const auto img = Draw(cam, dir_deg, 1.1, 1.6);
    std::vector<Eigen::Vector2d> pts;
    const WallLines w = FindWallLines(View(cam, img), cam, {}, &pts);
    ASSERT_TRUE(w.valid) << dir_deg;
    EXPECT_NEAR(RadToDeg(w.direction_rad), dir_deg, 1.0) << dir_deg;
    EXPECT_NEAR(w.HeadingDeg(), -dir_deg, 1.0) << dir_deg;
    EXPECT_GE(w.inliers, 10);
    // The main line is one of the two walls, the parallel one (both in view only when the
    // corridor runs within about 10° of the optical axis) the other.
    const double a = std::abs(w.offset_m - 1.1) < std::abs(w.offset_m + 1.6) ? 1.1 : -1.6;
    const double b = a > 0.0 ? -1.6 : 1.1;
    EXPECT_NEAR(w.offset_m, a, 0.08) << dir_deg;
    if (std::abs(dir_deg) <= 10.0) {
      EXPECT_GT(w.parallel_inliers, 0) << dir_deg;
      EXPECT_NEAR(w.parallel_offset_m, b, 0.12) << dir_deg;
    }
    EXPECT_LT(w.rms_m, 0.05);
    EXPECT_EQ(static_cast<int>(pts.size()), w.points);
  }
}

TEST(WallLines, CorridorAheadEndsAtAFootAcrossIt) {
  const CameraModel cam = Camera128();
  const WallLineOptions o;
  // Both walls in view, the floor's texture on to the range used: the corridor is free that far.
  const WallLines open = FindWallLines(View(cam, Draw(cam, 3.0, 1.0, 1.1)), cam);
  ASSERT_TRUE(open.valid);
  ASSERT_GT(open.parallel_inliers, 0);
  EXPECT_EQ(open.corridor_ahead_m, o.max_range_m);
  // A smooth end wall across the corridor: free to its foot, or about an image row short of it
  // (the nearest points of a foot seen slightly askew; measured 3.28, 3.63, 4.76 and 5.49 m),
  // never beyond it.
  for (const double end_m : {3.5, 4.0, 5.0, 6.0}) {
    const WallLines w = FindWallLines(View(cam, Draw(cam, 3.0, 1.0, 1.1, 30.0, true, end_m)), cam);
    ASSERT_TRUE(w.valid) << end_m;
    ASSERT_GT(w.parallel_inliers, 0) << end_m;
    EXPECT_LE(w.corridor_ahead_m, 1.01 * end_m) << end_m;
    EXPECT_GE(w.corridor_ahead_m, 0.88 * end_m) << end_m;
  }
  // One wall only in view (the corridor turned well off the optical axis): no corridor is shown.
  const WallLines one = FindWallLines(View(cam, Draw(cam, 25.0, 1.0, 1.1)), cam);
  ASSERT_TRUE(one.valid);
  EXPECT_EQ(one.parallel_inliers, 0);
  EXPECT_EQ(one.corridor_ahead_m, 0.0);
}

// The robot 0.5 m from the left wall, heading 20° toward it (the walls run 20° to the right):
// the wall stands within the bottom row's floor range on the left half of the view. The columns whose bottom rows see the
// wall are smooth there, those whose bottom rows see the floor carry its texture.
TEST(WallLines, BottomTextureIsSmoothWhereAWallStandsNearerThanTheBottomRow) {
  const CameraModel cam = Camera128();
  const auto img = Draw(cam, -20.0, 0.5, 2.0);
  const WallLines w = FindWallLines(View(cam, img), cam);
  ASSERT_EQ(static_cast<int>(w.bottom_texture.size()), cam.width);
  const double t = DegToRad(-20.0);
  const Eigen::Vector2d normal(-std::sin(t), std::cos(t));
  int walls = 0, floors = 0;
  for (int u = 1; u + 1 < cam.width; ++u) {
    // The column's bottom rows used (the last row has no second difference), and its neighbours.
    bool all_wall = true, all_floor = true;
    for (int du = -1; du <= 1; ++du)
      for (int v = cam.height - 2 - WallLineOptions{}.below_rows; v < cam.height; ++v) {
        const auto q = cam.FloorPoint({static_cast<double>(u + du), static_cast<double>(v)});
        const bool wall = !q || normal.dot(*q) >= 0.5;
        all_wall = all_wall && wall;
        all_floor = all_floor && !wall;
      }
    const float tex = w.bottom_texture[static_cast<std::size_t>(u)];
    if (all_wall) {
      ++walls;
      EXPECT_LT(tex, 0.5f) << u;
    } else if (all_floor) {
      ++floors;
      EXPECT_GT(tex, 5.0f) << u;
    }
  }
  EXPECT_GT(walls, 20);
  EXPECT_GT(floors, 20);
}

TEST(WallLines, HeadingIsTakenModuloNinetyDegrees) {
  WallLines w;
  w.direction_rad = DegToRad(80.0);  // an end wall's line seen with the robot turned 10° right of the axis
  EXPECT_NEAR(w.HeadingDeg(), 10.0, 1e-9);
  w.direction_rad = DegToRad(-50.0);
  EXPECT_NEAR(w.HeadingDeg(), -40.0, 1e-9);
  w.direction_rad = DegToRad(45.0);
  EXPECT_NEAR(w.HeadingDeg(), -45.0, 1e-9);
}

TEST(WallLines, SameFrameSameAnswer) {
  const CameraModel cam = Camera128();
  const auto img = Draw(cam, 12.0, 0.9, 1.4);
  const WallLines a = FindWallLines(View(cam, img), cam);
  const WallLines b = FindWallLines(View(cam, img), cam);
  ASSERT_TRUE(a.valid);
  EXPECT_EQ(a.direction_rad, b.direction_rad);
  EXPECT_EQ(a.offset_m, b.offset_m);
  EXPECT_EQ(a.inliers, b.inliers);
}

TEST(WallLines, NoFloorTextureNoReading) {
  // A smooth floor of the walls' own grey: nothing tells them apart.
  const CameraModel cam = Camera128();
  const auto img = Draw(cam, 5.0, 1.0, 1.0, 30.0, false);
  const WallLines w = FindWallLines(View(cam, img), cam);
  EXPECT_FALSE(w.valid);
  EXPECT_EQ(w.points, 0);
  const std::vector<std::uint8_t> flat(static_cast<std::size_t>(cam.width * cam.height), 128);
  EXPECT_FALSE(FindWallLines(View(cam, flat), cam).valid);
}

TEST(WallLines, TextureEndingAtOneRowSaysNothing) {
  // A wide floor whose texture fades out 4 m ahead: the boundary is one image row across the
  // view, a line across the optical axis whatever the walls do.
  const CameraModel cam = Camera128();
  const auto img = Draw(cam, 15.0, 30.0, 30.0, 4.0);
  const WallLines w = FindWallLines(View(cam, img), cam);
  EXPECT_FALSE(w.valid);
  EXPECT_GT(w.points, 20);
}

// The robot 0.35 m from the left wall, 5° toward it, the far wall out of view, a smooth end wall
// across the corridor 7 m on: its foot, nearly one image row, has more points than the near
// wall's base. drop_one_row_line leaves that row out and reads the near wall.
TEST(WallLines, AFootAcrossTheViewIsLeftOutForTheNearWallBesideIt) {
  const CameraModel cam = Camera128();
  const auto img = Draw(cam, 5.0, 0.35, 2.85, 30.0, true, 7.0);
  WallLineOptions o;
  const WallLines plain = FindWallLines(View(cam, img), cam, o);
  EXPECT_FALSE(plain.valid);
  o.drop_one_row_line = true;
  std::vector<Eigen::Vector2d> pts;
  const WallLines w = FindWallLines(View(cam, img), cam, o, &pts);
  ASSERT_TRUE(w.valid);
  EXPECT_NEAR(RadToDeg(w.direction_rad), 5.0, 1.5);
  EXPECT_NEAR(w.offset_m, 0.35, 0.05);
  EXPECT_EQ(w.points, plain.points);  // every point found is still reported
  EXPECT_EQ(static_cast<int>(pts.size()), w.points);
  // Where the near wall's base is the best line anyway, the option changes nothing.
  const auto two = Draw(cam, 3.0, 1.0, 1.1, 30.0, true, 5.0);
  const WallLines a = FindWallLines(View(cam, two), cam);
  const WallLines b = FindWallLines(View(cam, two), cam, o);
  ASSERT_TRUE(a.valid);
  EXPECT_EQ(a.direction_rad, b.direction_rad);
  EXPECT_EQ(a.offset_m, b.offset_m);
  EXPECT_EQ(a.parallel_offset_m, b.parallel_offset_m);
  EXPECT_EQ(a.corridor_ahead_m, b.corridor_ahead_m);
  // A floor's texture fading out along one row and nothing else: still no reading.
  EXPECT_FALSE(FindWallLines(View(cam, Draw(cam, 15.0, 30.0, 30.0, 4.0)), cam, o).valid);
}

TEST(WallLines, TooSmallOrEmptyFrameGivesNoReading) {
  const CameraModel cam = Camera128();
  std::vector<std::uint8_t> tiny(128 * 10, 100);
  EXPECT_FALSE(FindWallLines(GrayView{tiny.data(), 128, 10, 128}, cam).valid);
  EXPECT_FALSE(FindWallLines(GrayView{}, cam).valid);
}

TEST(WallLines, OptionsValidate) {
  EXPECT_EQ(WallLineOptions{}.Validate(), "");
  WallLineOptions o;
  o.base_row_offset = 9.0;
  EXPECT_NE(o.Validate().find("base_row_offset"), std::string::npos);
  o = {};
  o.smooth_ratio = 1.5;
  EXPECT_NE(o.Validate().find("smooth_ratio"), std::string::npos);
  o = {};
  o.min_inliers = 2;
  EXPECT_NE(o.Validate().find("min_inliers"), std::string::npos);
  o = {};
  o.inlier_m = 0.0;
  EXPECT_NE(o.Validate().find("inlier_m"), std::string::npos);
  o = {};
  o.foot_points = 0;
  EXPECT_NE(o.Validate().find("foot_points"), std::string::npos);
  o = {};
  o.inlier_m = 0.0;
  EXPECT_NE(o.Validate().find("inlier_m"), std::string::npos);
  o = {};
  o.max_range_m = std::nan("");
  EXPECT_NE(o.Validate().find("max_range_m"), std::string::npos);
}

}  // namespace
}  // namespace squint::explore
