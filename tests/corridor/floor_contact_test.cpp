// The end wall's floor contact on constructed frames: a plain wall standing on the floor at a
// known distance, seen by a known camera, reads that distance; frames without such an edge read
// nothing; the Perceiver's fusion takes it only when the cues' fused distance agrees or, with the
// motion test, when its readings move under the odometry as a floor point does.
#include "squint/corridor/floor_contact.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "squint/core/error.hpp"
#include "squint/corridor/perceiver.hpp"

namespace squint::corridor {
namespace {

CameraModel Camera(double pitch_deg) {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 188.0;
  c.cx = 79.5;
  c.cy = 59.5;
  c.height_m = 0.95;
  c.pitch_deg = pitch_deg;
  return c;
}

// Each pixel's ray is traced: it meets the floor (grey `floor`, with a gentle ramp) before the
// wall at distance `wall_m` ahead, or the wall (grey `wall`, darkening downward like a lit wall).
std::vector<std::uint8_t> WallFrame(const CameraModel& cam, double wall_m, int floor, int wall) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray = cam.PixelRayRobot({static_cast<double>(u), static_cast<double>(v)});
      double g = wall;
      if (ray.z() < 0.0) {
        const double t = cam.height_m / -ray.z();  // along the ray to the floor
        if (t * ray.x() < wall_m) g = floor + 0.5 * t;  // floor before the wall
      }
      if (g == wall) {
        const double z = cam.height_m + (wall_m / ray.x()) * ray.z();  // height on the wall
        g = wall - 3.0 * std::max(0.0, cam.height_m - z);
      }
      px[static_cast<std::size_t>(v * cam.width + u)] = static_cast<std::uint8_t>(std::lround(g));
    }
  return px;
}

PixelView View(const std::vector<std::uint8_t>& px, const CameraModel& cam) {
  return PixelView{px.data(), cam.width, cam.height, cam.width, 1};
}

TEST(FloorContact, PlainWallReadsItsDistance) {
  for (const double pitch : {0.0, -6.0}) {
    const CameraModel cam = Camera(pitch);
    FloorContact fc(cam, FloorContactOptions{});
    for (const double d : {3.5, 5.0, 9.0, 14.0}) {  // nearer, the wall's base is below the view (3.0 m level)
      const auto px = WallFrame(cam, d, 90, 170);
      const std::optional<double> r = fc.Measure(View(px, cam));
      ASSERT_TRUE(r) << d << " m, pitch " << pitch;
      // One row near the horizon spans d² / (h · fy) metres: the sub-pixel edge keeps the error
      // to a fraction of that.
      const double row_m = d * d / (cam.height_m * cam.fy);
      EXPECT_NEAR(*r, d, std::max(0.02, 0.5 * row_m)) << d << " m, pitch " << pitch;
    }
  }
}

TEST(FloorContact, NoEdgeOrWrongSizeReadsNothing) {
  const CameraModel cam = Camera(-6.0);
  FloorContact fc(cam, FloorContactOptions{});
  const std::vector<std::uint8_t> flat(static_cast<std::size_t>(cam.width * cam.height), 128);
  EXPECT_FALSE(fc.Measure(View(flat, cam)));
  CameraModel small = cam;
  small.width = 80;
  const auto px = WallFrame(cam, 6.0, 90, 170);
  EXPECT_FALSE(fc.Measure(PixelView{px.data(), 80, cam.height, cam.width, 1}));
  // A wall beyond max_m reads nothing; a wall nearer than the bottom row's floor (2.2 m here)
  // fills the view below the horizon: nothing either.
  FloorContactOptions near_only;
  near_only.max_m = 4.0;
  FloorContact fc4(cam, near_only);
  EXPECT_FALSE(fc4.Measure(View(px, cam)));
  EXPECT_TRUE(fc4.Measure(View(WallFrame(cam, 3.0, 90, 170), cam)));
  EXPECT_FALSE(fc4.Measure(View(WallFrame(cam, 1.5, 90, 170), cam)));
}

TEST(FloorContact, CameraWithoutHeightIsAnError) {
  CameraModel cam = Camera(0.0);
  cam.height_m = 0.0;
  EXPECT_THROW(FloorContact(cam, FloorContactOptions{}), Error);
  FloorContactOptions bad;
  bad.min_step = 0.0;
  EXPECT_THROW(FloorContact(Camera(0.0), bad), Error);
}

// Options whose cues' fused distance is Jeffrey's constant reading of beta2 (alpha2 = 0): 20 m,
// far from the walls the floor-contact tests place at 3-5 m; the gate off.
CorridorOptions JeffreyAt20m() {
  CorridorOptions o;
  o.gate.enabled = false;
  o.distance.enabled = {false, true, false};
  o.distance.alpha2 = 0.0;
  o.distance.beta2 = 20.0;
  return o;
}

// The Perceiver reports the floor contact's temporal median as dist_floor_m; it becomes the fused
// distance only where the cues' fused distance lies within agreement_ratio of it.
TEST(FloorContact, PerceiverFusesItOnlyWhenTheCuesAgree) {
  const CameraModel cam = Camera(-6.0);
  for (const double ratio : {0.0, 0.5}) {
    CorridorOptions o = JeffreyAt20m();
    o.distance.floor_contact.agreement_ratio = ratio;
    Perceiver perceiver(o, cam);
    PerceptionResult r;
    for (int i = 0; i < 6; ++i) {
      const double d = 4.0 - 0.1 * i;
      const auto px = WallFrame(cam, d, 90 + i, 170 - i);
      r = perceiver.Process(View(px, cam), 0.1, 0.25);
      ASSERT_TRUE(r.dist_floor_raw_m);
      EXPECT_NEAR(*r.dist_floor_raw_m, d, 0.05);
    }
    ASSERT_TRUE(r.dist_floor_m);
    EXPECT_NEAR(*r.dist_floor_m, 3.5, 0.05);  // the median moved to the current frame
    ASSERT_TRUE(r.dist_end_m);
    if (ratio == 0.0) EXPECT_NEAR(*r.dist_end_m, *r.dist_floor_m, 1e-12);  // no check: it overrides
    else EXPECT_GT(*r.dist_end_m, 10.0);                                  // 20 m against 3.5 m: the cues stand
  }
}

// A plain wall `wall_m` ahead whose foot is a dark contact shadow on the floor, `shadow_m` deep:
// the wall (grey `wall`) steps down into the shadow (`shadow`) at the foot, the shadow steps up to
// the floor (`floor`) a row or two below, a stronger step than the foot's.
std::vector<std::uint8_t> ShadowFrame(const CameraModel& cam, double wall_m, double shadow_m, int floor, int shadow,
                                      int wall) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray = cam.PixelRayRobot({static_cast<double>(u), static_cast<double>(v)});
      int g = wall;
      if (ray.z() < 0.0) {
        const double x = cam.height_m / -ray.z() * ray.x();  // the floor point's distance ahead
        if (x < wall_m) g = x < wall_m - shadow_m ? floor : shadow;
      }
      px[static_cast<std::size_t>(v * cam.width + u)] = static_cast<std::uint8_t>(g);
    }
  return px;
}

// By default the refinement moves to the shadow's stronger lower edge (on the floor, nearer than
// the wall); with refine_same_sign it keeps the foot.
TEST(FloorContact, SameSignRefinementKeepsTheFootAboveAContactShadow) {
  const CameraModel cam = Camera(-6.0);
  FloorContactOptions same;
  same.refine_same_sign = true;
  FloorContact any_sign(cam, FloorContactOptions{}), same_sign(cam, same);
  for (const double d : {5.0, 6.0, 8.0}) {
    const auto px = ShadowFrame(cam, d, 0.3, 190, 110, 170);
    const std::optional<double> a = any_sign.Measure(View(px, cam));
    const std::optional<double> b = same_sign.Measure(View(px, cam));
    ASSERT_TRUE(a && b) << d;
    const double row_m = d * d / (cam.height_m * cam.fy);  // one row near the foot, metres
    EXPECT_NEAR(*b, d, 0.5 * row_m) << d;
    EXPECT_LT(*a, d - 0.15) << d;  // the shadow's far side: on the floor, nearer
  }
  // Without a shadow both read the plain wall alike.
  const auto plain = WallFrame(cam, 6.0, 90, 170);
  EXPECT_NEAR(*same_sign.Measure(View(plain, cam)), *any_sign.Measure(View(plain, cam)), 0.2);
}

// A brick-like end wall at `wall_m`: grey `wall` with a dark mortar line (grey `mortar`) 0.05 m
// high every `course_m` from `course_m` up, standing on the floor (grey `floor`, with a gentle
// ramp). The foot (wall against floor) is the column's strongest step; the mortar lines below the
// camera's height are weaker steps above it.
std::vector<std::uint8_t> LinedWallFrame(const CameraModel& cam, double wall_m, double course_m, int floor, int wall,
                                         int mortar) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray = cam.PixelRayRobot({static_cast<double>(u), static_cast<double>(v)});
      double g = -1.0;
      if (ray.z() < 0.0) {
        const double t = cam.height_m / -ray.z();
        if (t * ray.x() < wall_m) g = floor + 0.5 * t;
      }
      if (g < 0.0) {
        const double z = cam.height_m + (wall_m / ray.x()) * ray.z();  // height on the wall
        const double in_course = std::fmod(z, course_m);
        g = z >= course_m - 1e-9 && in_course < 0.05 ? mortar : wall;
      }
      px[static_cast<std::size_t>(v * cam.width + u)] = static_cast<std::uint8_t>(std::lround(g));
    }
  return px;
}

// The first edge below the horizon of a lined end wall is a mortar line, which reads farther
// than the wall; the lined-wall rule sees the lines just above the horizon and takes the foot.
// On a plain wall it changes nothing, even where a floor edge below the foot is stronger.
TEST(FloorContact, LinedWallRuleFindsTheFootBelowMortarLines) {
  const CameraModel cam = Camera(-6.0);
  FloorContactOptions lined;
  lined.lined_wall_rel_step = 0.5;
  FloorContact first(cam, FloorContactOptions{}), rule(cam, lined);
  for (const double d : {4.0, 5.0, 6.0}) {
    // Mortar at 0.6 and 1.2 m: the first reads 3.2 times too far, the second is above the horizon.
    const auto px = LinedWallFrame(cam, d, 0.6, 90, 200, 175);  // foot step 100+, mortar 25
    const std::optional<double> a = first.Measure(View(px, cam));
    const std::optional<double> b = rule.Measure(View(px, cam));
    ASSERT_TRUE(a && b) << d;
    const double row_m = d * d / (cam.height_m * cam.fy);
    EXPECT_GT(*a, d + 0.3) << d;  // a mortar line: above the foot, read too far
    EXPECT_NEAR(*b, d, std::max(0.02, 0.5 * row_m)) << d;
  }
  // A plain wall with a floor stripe before it that steps more than the wall's foot: not lined,
  // so the first edge (the foot) stands.
  for (const double d : {5.0, 9.0}) {
    auto px = WallFrame(cam, d, 150, 170);
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d ray = cam.PixelRayRobot({static_cast<double>(u), static_cast<double>(v)});
        if (ray.z() >= 0.0) continue;
        const double x = cam.height_m / -ray.z() * ray.x();
        if (x < d - 1.0 && x > d - 1.5) px[static_cast<std::size_t>(v * cam.width + u)] = 40;
      }
    const std::optional<double> a = first.Measure(View(px, cam));
    const std::optional<double> b = rule.Measure(View(px, cam));
    ASSERT_TRUE(a && b) << d;
    EXPECT_EQ(*a, *b) << d;
    EXPECT_NEAR(*b, d, std::max(0.02, 0.5 * d * d / (cam.height_m * cam.fy))) << d;
  }
}

// Where the lined-wall rule searches again, the columns' edges must lie on one line, as an end
// wall's foot does. A constructed wall (level camera, horizon at row 59.5): courses above the
// horizon every 2 rows (lined), a faint course just below it (the first edge), and a strong step
// at row `foot(u)` below. With one foot row for every column the rule reads that row's floor
// point; with the strong step at three rows in blocks of columns (a brick wall's courses found
// again) it reads nothing.
std::vector<std::uint8_t> CoursedFrame(const CameraModel& cam, int (*foot)(int)) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      int g = 150;
      if (v >= 50 && v < 60) g = (v / 2) % 2 == 1 ? 175 : 150;  // courses above the horizon
      else if (v >= 62) g = v > foot(u) ? 40 : 140;  // a faint course, then the strong step
      px[static_cast<std::size_t>(v * cam.width + u)] = static_cast<std::uint8_t>(g);
    }
  return px;
}

TEST(FloorContact, LinedWallRuleNeedsTheColumnsOnOneLine) {
  const CameraModel cam = Camera(0.0);
  FloorContactOptions lined;
  lined.lined_wall_rel_step = 0.5;
  FloorContact first(cam, FloorContactOptions{}), rule(cam, lined);
  const auto one = CoursedFrame(cam, [](int) { return 84; });
  const std::optional<double> a = rule.Measure(View(one, cam));
  ASSERT_TRUE(a);
  EXPECT_NEAR(*a, cam.height_m * cam.fy / (84.5 - 59.5), 0.01);  // the edge between rows 84 and 85
  EXPECT_FALSE(first.Measure(View(one, cam)));  // without the rule: the faint course, 89 m (> max_m)
  const auto scattered = CoursedFrame(cam, [](int u) { return 80 + 6 * ((u / 4) % 3); });
  EXPECT_FALSE(rule.Measure(View(scattered, cam)));
  // Each block alone is one line and reads its own foot.
  const auto block = CoursedFrame(cam, [](int) { return 92; });
  const std::optional<double> b = rule.Measure(View(block, cam));
  ASSERT_TRUE(b);
  EXPECT_NEAR(*b, cam.height_m * cam.fy / (92.5 - 59.5), 0.01);
}

TEST(FloorContactOptions, LinedWallRuleIsValidated) {
  FloorContactOptions o;
  EXPECT_EQ(o.lined_wall_rel_step, 0.0);  // off by default
  for (const double bad : {-0.1, 1.5, std::nan("")}) {
    o.lined_wall_rel_step = bad;
    EXPECT_NE(o.Validate().find("lined_wall_rel_step"), std::string::npos) << bad;
    EXPECT_THROW(FloorContact(Camera(0.0), o), Error) << bad;
  }
  o.lined_wall_rel_step = 1.0;
  EXPECT_TRUE(o.Validate().empty());
}

FloorContactOptions MotionOptions() {
  FloorContactOptions o;
  o.motion_window_m = 2.0;  // 0.5 row, 80 % of at least 5 readings: the defaults
  return o;
}

// The row of the floor at distance d: at d → ∞ the horizon; at the camera's own pitch angle
// below it, the image centre.
TEST(FloorMotionCheck, FloorRowIsThePinholeProjection) {
  const CameraModel cam = Camera(-6.0);
  const FloorMotionCheck check(cam, MotionOptions());
  EXPECT_NEAR(check.FloorRow(1e9), cam.HorizonRow(), 1e-6);
  EXPECT_NEAR(check.FloorRow(cam.height_m / std::tan(6.0 * M_PI / 180.0)), cam.cy, 1e-9);
  // Pitch 0: row = cy + fy · h / d.
  const FloorMotionCheck level(Camera(0.0), MotionOptions());
  EXPECT_NEAR(level.FloorRow(5.0), 59.5 + 188.0 * 0.95 / 5.0, 1e-9);
}

// Readings of one floor point 12 m ahead, 0.1 m per frame: consistent once they span half the
// window (1 m) with at least 5 readings; the same with every sixth reading several rows off (4 of
// the 21 readings in the 2 m window, 19 %), not with every third (7 of 21).
TEST(FloorMotionCheck, AFloorPointPassesOnceTheWindowIsSpanned) {
  const CameraModel cam = Camera(-6.0);
  for (const int outlier_every : {0, 6, 3}) {
    FloorMotionCheck check(cam, MotionOptions());
    bool last = false;
    for (int i = 0; i <= 30; ++i) {
      const double t = 0.1 * i;
      double r = 12.0 - t;
      if (outlier_every > 0 && i % outlier_every == 0) r *= 0.7;  // several rows nearer
      last = check.Update(t, r);
      if (i < 10) {
        EXPECT_FALSE(last) << i;  // the readings span less than 1 m
      }
    }
    EXPECT_EQ(last, outlier_every != 3) << outlier_every;
  }
}

// A feature at height z on a wall D ahead reads (D − t) · h / (h − z) on the floor model: 0.3 m
// up a wall 12 m ahead reads 17.5 m and closes 1.46 times as fast as the floor; a detector
// alternating between two brick courses scatters. Neither passes. Nor does a frame without a
// reading, and a Reset forgets the window.
TEST(FloorMotionCheck, AWallFeatureOrAJumpingEdgeFails) {
  const CameraModel cam = Camera(-6.0);
  const double h = cam.height_m;
  FloorMotionCheck course(cam, MotionOptions()), jumping(cam, MotionOptions()), floor(cam, MotionOptions());
  bool c = true, j = true, f = false;
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * i, d = 8.0 - t;
    c = course.Update(t, d * h / (h - 0.3));
    j = jumping.Update(t, d * h / (h - (i % 2 == 0 ? 0.1 : 0.3)));
    f = floor.Update(t, d);
  }
  EXPECT_FALSE(c);
  EXPECT_FALSE(j);
  EXPECT_TRUE(f);
  EXPECT_FALSE(floor.Update(2.1, std::nullopt));  // this frame has no reading
  floor.Reset();
  EXPECT_FALSE(floor.Update(2.2, 5.8));
}

// An edge fixed in the image (a wall's course at the camera's height reads the same far
// distance frame after frame) passes the row test wherever a floor point barely moves: 30 m ahead,
// 2 m of travel moves the floor 0.43 row with this camera, less than the 0.5-row tolerance. Such a
// window says nothing and fails; a floor point 12 m ahead crosses 3.6 rows and passes.
TEST(FloorMotionCheck, AWindowThatCannotTellFails) {
  const CameraModel cam = Camera(0.0);
  FloorMotionCheck fixed(cam, MotionOptions()), floor(cam, MotionOptions());
  bool x = true, f = false;
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * i;
    x = fixed.Update(t, 30.0);
    f = floor.Update(t, 12.0 - t);
  }
  EXPECT_LT(fixed.FloorRow(28.0) - fixed.FloorRow(30.0), 0.5);
  EXPECT_FALSE(x);
  EXPECT_TRUE(f);
}

// With the motion test on, the floor contact becomes the fused distance although the cues'
// fused distance (Jeffrey's constant 20 m) disagrees, once its readings span half the window.
TEST(FloorContact, PerceiverFusesItWhenItMovesAsTheFloor) {
  const CameraModel cam = Camera(-6.0);
  CorridorOptions o = JeffreyAt20m();
  o.distance.floor_contact.motion_window_m = 1.0;
  Perceiver perceiver(o, cam);
  PerceptionResult r;
  for (int i = 0; i < 12; ++i) {
    const double d = 5.0 - 0.1 * i;
    const auto px = WallFrame(cam, d, 90 + i, 170 - i);
    r = perceiver.Process(View(px, cam), 0.1, 0.25);
    ASSERT_TRUE(r.dist_floor_m);
    if (i == 0) continue;  // no previous frame: no Jeffrey yet
    ASSERT_TRUE(r.dist_end_m);
    if (i < 5) {  // less than 0.5 m of readings: the cues stand
      EXPECT_FALSE(r.dist_floor_moves_as_floor) << i;
      EXPECT_GT(*r.dist_end_m, 10.0) << i;
    }
  }
  EXPECT_TRUE(r.dist_floor_moves_as_floor);
  EXPECT_NEAR(*r.dist_end_m, *r.dist_floor_m, 1e-12);
  EXPECT_NEAR(*r.dist_end_m, 3.9, 0.05);
}

TEST(FloorContactOptions, MotionTestOptionsAreValidated) {
  FloorContactOptions o = MotionOptions();
  EXPECT_TRUE(o.Validate().empty());
  o.motion_window_m = -1.0;
  EXPECT_NE(o.Validate().find("motion_window_m"), std::string::npos);
  o = MotionOptions();
  o.motion_tol_rows = 0.0;
  EXPECT_NE(o.Validate().find("motion_tol_rows"), std::string::npos);
  o = MotionOptions();
  o.motion_min_fraction = 1.5;
  EXPECT_NE(o.Validate().find("motion_min_fraction"), std::string::npos);
  o = MotionOptions();
  o.motion_min_readings = 1;
  EXPECT_NE(o.Validate().find("motion_min_readings"), std::string::npos);
  EXPECT_THROW(FloorMotionCheck(Camera(0.0), o), Error);
}

}  // namespace
}  // namespace squint::corridor
