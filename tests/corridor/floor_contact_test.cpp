// The end wall's floor contact on constructed frames: a plain wall standing on the floor at a
// known distance, seen by a known camera, reads that distance; frames without such an edge read
// nothing; the Perceiver's fusion takes it only when the cues' fused distance agrees.
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

// The Perceiver reports the floor contact's temporal median as dist_floor_m; it becomes the fused
// distance only where the cues' fused distance lies within agreement_ratio of it.
TEST(FloorContact, PerceiverFusesItOnlyWhenTheCuesAgree) {
  const CameraModel cam = Camera(-6.0);
  for (const double ratio : {0.0, 0.5}) {
    CorridorOptions o;
    o.gate.enabled = false;
    o.distance.floor_contact.agreement_ratio = ratio;
    // The cues' fused distance: Jeffrey's constant reading of beta2 (alpha2 = 0), far from 4 m.
    o.distance.enabled = {false, true, false};
    o.distance.alpha2 = 0.0;
    o.distance.beta2 = 20.0;
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

}  // namespace
}  // namespace squint::corridor
