// Constructed IPT geometry: a floor point gives D = 0, an elevated point the analytic D, a mirror
// image a negative signed D and a zero mirror-aware D; the horizon row for a known pitch (paper §6.2: v < 65).
#include "squint/obstacles/ipt_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "squint/obstacles/zones.hpp"

namespace squint::obstacles {
namespace {

CameraModel PaperCamera() {
  // §6.1–6.2: 256×192, f = 3.720 mm with 4 × 4.65 µm pixels (k_v = 1000 / (4 · 4.65) px/mm),
  // camera 430 mm high, pitch −9°.
  CameraModel c;
  c.width = 256, c.height = 192;
  c.fx = c.fy = 3.720 * 1000.0 / (4.0 * 4.65);
  c.cx = 127.5, c.cy = 95.5;
  c.height_m = 0.43, c.pitch_deg = -9.0;
  return c;
}

// The pixel at which the camera of world_T_robot sees a world point.
Eigen::Vector2d See(const CameraModel& cam, const Pose2& world_T_robot, const Eigen::Vector3d& world) {
  const Eigen::Vector2d xy = world_T_robot.Inverse().Apply(world.head<2>());
  const auto px = cam.Project({xy.x(), xy.y(), world.z()});
  EXPECT_TRUE(px.has_value());
  return px.value_or(Eigen::Vector2d::Zero());
}

struct Motion {
  Pose2 a, b;
};

class IptGeometryTest : public ::testing::TestWithParam<Motion> {};

TEST_P(IptGeometryTest, FloorPointHasZeroDiscrepancyAndElevatedPointTheAnalyticOne) {
  const CameraModel cam = PaperCamera();
  const auto [a, b] = GetParam();
  const double moved = std::hypot(b.x - a.x, b.y - a.y);
  for (const Eigen::Vector3d& base : {Eigen::Vector3d(1.5, 0.2, 0.0), Eigen::Vector3d(2.5, -0.4, 0.0)}) {
    // The point `base` ahead of the first pose, on the floor.
    const Eigen::Vector2d ahead = a.Apply(base.head<2>());
    const Eigen::Vector3d floor_world(ahead.x(), ahead.y(), 0.0);
    const auto d_floor = Discrepancy(cam, a, See(cam, a, floor_world), b, See(cam, b, floor_world));
    ASSERT_TRUE(d_floor.has_value());
    EXPECT_NEAR(*d_floor, 0.0, 1e-9);
    // Floor back-projection recovers the point itself.
    const auto back = FloorPointWorld(cam, b, See(cam, b, floor_world));
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR((*back - floor_world.head<2>()).norm(), 0.0, 1e-9);

    // A point z above the floor back-projects to C + s (P − C), s = h / (h − z), so its floor
    // point moves by (1 − s) dC: D = |dC| z / (h − z), directed against the camera's motion.
    for (double z : {0.1, 0.2, 0.35}) {
      const Eigen::Vector3d p(floor_world.x(), floor_world.y(), z);
      const auto d = Discrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      const auto sd = SignedDiscrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(d && sd);
      const double expected = moved * z / (cam.height_m - z);
      EXPECT_NEAR(*d, expected, 1e-9 + 1e-9 * expected);
      EXPECT_NEAR(*sd, expected, 1e-9 + 1e-9 * expected);
    }
    // A mirror image in a specular floor: a virtual point below it. Its floor point moves with the
    // camera: signed D = −|dC| |z| / (h + |z|).
    const Eigen::Vector3d mirror(floor_world.x(), floor_world.y(), -0.3);
    const auto sd = SignedDiscrepancy(cam, a, See(cam, a, mirror), b, See(cam, b, mirror));
    ASSERT_TRUE(sd.has_value());
    EXPECT_NEAR(*sd, -moved * 0.3 / (cam.height_m + 0.3), 1e-9);
  }
}

// The mirror-aware discrepancy: the floor point of a static point moves by k·dC with k = 0 on the floor,
// 0 < k < 1 for a mirror image below a specular floor and k < 0 above the floor; the distance to the
// segment k ∈ [0, 1] is D above the floor and 0 for the floor and its reflections. A floor point
// seen displaced sideways by 5 mm scores 5 mm; one displaced along the motion by 1.5·dC, 0.5·|dC|.
TEST_P(IptGeometryTest, MirrorAwareDiscrepancyIsDAboveTheFloorAndZeroForReflections) {
  const CameraModel cam = PaperCamera();
  const auto [a, b] = GetParam();
  const Eigen::Vector2d dc = b.Apply(cam.RobotCameraCentre().head<2>()) - a.Apply(cam.RobotCameraCentre().head<2>());
  for (const Eigen::Vector3d& base : {Eigen::Vector3d(1.5, 0.2, 0.0), Eigen::Vector3d(2.5, -0.4, 0.0)}) {
    const Eigen::Vector2d ahead = a.Apply(base.head<2>());
    for (double z : {0.0, -0.05, -0.3, -2.0}) {  // the floor and mirror images below it
      const Eigen::Vector3d p(ahead.x(), ahead.y(), z);
      const auto plain = Discrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      const auto m = MirrorAwareDiscrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(plain && m);
      const auto all = AllDiscrepancies(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(all.has_value());
      EXPECT_NEAR(all->plain_m, *plain, 1e-12);
      EXPECT_NEAR(all->mirror_aware_m, *m, 1e-12);
      EXPECT_NEAR(all->signed_m, *SignedDiscrepancy(cam, a, See(cam, a, p), b, See(cam, b, p)), 1e-12);
      EXPECT_NEAR(*plain, dc.norm() * -z / (cam.height_m - z), 1e-9) << "z " << z;
      EXPECT_NEAR(*m, 0.0, 1e-9) << "z " << z;
    }
    for (double z : {0.05, 0.2, 0.35}) {  // above the floor: D itself
      const Eigen::Vector3d p(ahead.x(), ahead.y(), z);
      const auto plain = Discrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      const auto m = MirrorAwareDiscrepancy(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(plain && m);
      EXPECT_GT(*m, 0.0);
      EXPECT_NEAR(*m, *plain, 1e-9) << "z " << z;
      const auto all = AllDiscrepancies(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(all.has_value());
      EXPECT_NEAR(all->mirror_aware_m, *m, 1e-12);
      EXPECT_NEAR(all->signed_m, *SignedDiscrepancy(cam, a, See(cam, a, p), b, See(cam, b, p)), 1e-12);
    }
    // Floor points seen where the later frame shows the floor 5 mm to the side of the motion, and
    // 1.5·dC along it (more than any static point can move).
    const Eigen::Vector3d floor_world(ahead.x(), ahead.y(), 0.0);
    const Eigen::Vector2d side = Eigen::Vector2d(-dc.y(), dc.x()).normalized() * 0.005;
    const Eigen::Vector3d shifted(ahead.x() + side.x(), ahead.y() + side.y(), 0.0);
    const auto m_side = MirrorAwareDiscrepancy(cam, a, See(cam, a, floor_world), b, See(cam, b, shifted));
    ASSERT_TRUE(m_side.has_value());
    EXPECT_NEAR(*m_side, 0.005, 1e-9);
    const Eigen::Vector3d beyond(ahead.x() + 1.5 * dc.x(), ahead.y() + 1.5 * dc.y(), 0.0);
    const auto m_beyond = MirrorAwareDiscrepancy(cam, a, See(cam, a, floor_world), b, See(cam, b, beyond));
    ASSERT_TRUE(m_beyond.has_value());
    EXPECT_NEAR(*m_beyond, 0.5 * dc.norm(), 1e-9);
  }
  // No motion of the camera centre: undefined.
  EXPECT_FALSE(MirrorAwareDiscrepancy(cam, a, {100, 150}, a, {100, 150}).has_value());
}

// The odometry epipolar residual: 0 for every static point (floor, elevated, mirror image below the
// floor), and for a point displaced along the image's vertical by δ px off the epipolar line, about δ
// times the sine of the angle between the epipolar line and the vertical.
TEST_P(IptGeometryTest, MotionEpipolarErrorIsZeroForStaticPointsAndGrowsOffTheEpipolarLine) {
  const CameraModel cam = PaperCamera();
  const auto [a, b] = GetParam();
  for (const Eigen::Vector3d& base : {Eigen::Vector3d(1.5, 0.2, 0.0), Eigen::Vector3d(2.5, -0.4, 0.0)}) {
    const Eigen::Vector2d ahead = a.Apply(base.head<2>());
    for (double z : {0.0, 0.2, 0.35, -0.3}) {
      const Eigen::Vector3d p(ahead.x(), ahead.y(), z);
      const auto e = MotionEpipolarErrorPx(cam, a, See(cam, a, p), b, See(cam, b, p));
      ASSERT_TRUE(e.has_value());
      EXPECT_NEAR(*e, 0.0, 1e-6) << "z " << z;
    }
    // Move the later pixel perpendicular to its epipolar line by 1.5 px: the epipolar line through
    // the true later pixel is the image of the earlier ray; its direction is found from two points.
    const Eigen::Vector3d p(ahead.x(), ahead.y(), 0.1);
    const Eigen::Vector2d pa = See(cam, a, p), pb = See(cam, b, p);
    const Eigen::Vector3d far_point = [&] {  // another point on the earlier pixel's ray, 3× farther
      const Eigen::Vector3d ray = cam.PixelRayRobot(pa);
      const double t = (p - Eigen::Vector3d(a.x, a.y, cam.height_m)).norm() * 3.0;
      const Eigen::Vector2d xy = a.Apply((cam.RobotCameraCentre() + t * ray).head<2>());
      return Eigen::Vector3d(xy.x(), xy.y(), cam.height_m + t * ray.z());
    }();
    const Eigen::Vector2d along = (See(cam, b, far_point) - pb).normalized();
    const Eigen::Vector2d normal(-along.y(), along.x());
    const auto e = MotionEpipolarErrorPx(cam, a, pa, b, pb + 1.5 * normal);
    ASSERT_TRUE(e.has_value());
    EXPECT_NEAR(*e, 1.5, 0.1);  // pixel distance ≈ angle × f near the image centre
    // Sliding along the epipolar line keeps it on the line (any depth is a static point).
    const auto e_along = MotionEpipolarErrorPx(cam, a, pa, b, pb + 3.0 * along);
    ASSERT_TRUE(e_along.has_value());
    EXPECT_NEAR(*e_along, 0.0, 1e-3);
  }
  // No motion of the camera centre: undefined.
  EXPECT_FALSE(MotionEpipolarErrorPx(cam, a, {100, 150}, a, {100, 150}).has_value());
}

INSTANTIATE_TEST_SUITE_P(Motions, IptGeometryTest,
                         ::testing::Values(Motion{{0, 0, 0}, {0.031, 0, 0}},                // the paper's step
                                           Motion{{1.0, -2.0, 0.7}, {1.0 + 0.05 * std::cos(0.7),
                                                                      -2.0 + 0.05 * std::sin(0.7), 0.75}},  // turning
                                           Motion{{0, 0, 0}, {0.02, 0.01, -0.05}}));

TEST(IptGeometry, HorizonRowForKnownPitchMatchesEquation10) {
  const CameraModel cam = PaperCamera();
  // Eq. 10: v < v0 + k_v f tan(φ) = cy + fy tan(−9°); the paper rounds it to "v < 65".
  const double horizon = cam.cy + cam.fy * std::tan(-9.0 * M_PI / 180.0);
  EXPECT_NEAR(horizon, 63.8, 0.1);
  EXPECT_LT(horizon, 65.0);
  for (double u : {0.0, 127.5, 255.0}) {
    EXPECT_TRUE(AboveHorizon(cam, {u, horizon - 0.01}));
    EXPECT_FALSE(AboveHorizon(cam, {u, horizon + 0.01}));
    EXPECT_FALSE(FloorPointWorld(cam, Pose2{}, {u, horizon - 0.01}).has_value());
  }
  // Level camera: the horizon is the principal row.
  CameraModel level = cam;
  level.pitch_deg = 0.0;
  EXPECT_TRUE(AboveHorizon(level, {10.0, level.cy - 0.01}));
  EXPECT_FALSE(AboveHorizon(level, {10.0, level.cy + 0.01}));
  // The zone layout starts zone 2 at the same row (on a 0.25-row grid).
  const ZoneLayout zones = ComputeZoneLayout(cam, ZoneOptions{});
  EXPECT_NEAR(zones.horizon_row, horizon, 0.25);
  EXPECT_LE(zones.horizon_row, zones.zone2_end_row);
  EXPECT_LE(zones.zone2_end_row, zones.zone1_end_row);
}

TEST(IptGeometry, SimulatedDiscrepancyMapVanishesWhereTheSphereIsUnderTheFloor) {
  const CameraModel cam = PaperCamera();
  ZoneOptions opt;  // DST 1.5 m, 31 mm step (§4.2)
  const auto map = SimulateDiscrepancyMap(cam, opt);
  ASSERT_EQ(map.size(), 256u * 192u);
  auto at = [&](int u, int v) { return map[static_cast<std::size_t>(v) * 256 + static_cast<std::size_t>(u)]; };
  // Bottom row centre: the ray meets the floor well within 1.5 m, D = 0.
  EXPECT_EQ(at(128, 191), 0.0);
  // Just below the horizon, the 1.5 m point is z ≈ h − 1.5 sin(small) above the floor: analytic D.
  const int v = 70;
  const Eigen::Vector3d ray = cam.PixelRayRobot({128, v});
  const double z = cam.height_m + 1.5 * ray.z();
  EXPECT_NEAR(at(128, v), opt.step_m * z / (cam.height_m - z), 1e-6);
  for (double d : map) EXPECT_TRUE(std::isfinite(d) && d >= 0.0);
}

}  // namespace
}  // namespace squint::obstacles

namespace squint::obstacles {
namespace {

// PairGeometry (what the pipeline runs per feature) gives exactly AboveHorizon, AllDiscrepancies and
// MotionEpipolarErrorPx, with and without lens distortion, turning and straight motions.
TEST(PairGeometry, EqualsTheSingleFunctions) {
  CameraModel plain = PaperCamera();
  CameraModel distorted = plain;
  distorted.distortion = {-0.12, 0.03, 0.001, -0.0005, 0.0};
  const Pose2 poses[][2] = {{{0.0, 0.0, 0.0}, {0.031, 0.0, 0.0}},
                            {{1.2, -0.4, 0.3}, {1.23, -0.39, 0.33}},
                            {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.2}}};  // pure rotation: no baseline
  for (const CameraModel& cam : {plain, distorted})
    for (const auto& [a, b] : poses) {
      const PairGeometry geometry(cam, a, b);
      for (double v = 0.0; v < 192.0; v += 7.3)
        for (double u = 0.0; u < 256.0; u += 11.7) {
          const Eigen::Vector2d previous(u, v), current(u + 1.3 - v * 0.01, v + 0.7);
          const FeatureMeasures m = geometry.Measure(previous, current);
          EXPECT_EQ(m.above_horizon, AboveHorizon(cam, current));
          const auto epi = MotionEpipolarErrorPx(cam, a, previous, b, current);
          ASSERT_EQ(m.motion_epipolar_px.has_value(), epi.has_value());
          if (epi) {
            EXPECT_EQ(*m.motion_epipolar_px, *epi);
          }
          if (m.above_horizon) continue;
          const auto d = AllDiscrepancies(cam, a, previous, b, current);
          ASSERT_EQ(m.discrepancies.has_value(), d.has_value()) << u << " " << v;
          if (!d) continue;
          EXPECT_EQ(m.discrepancies->plain_m, d->plain_m);
          EXPECT_EQ(m.discrepancies->signed_m, d->signed_m);
          EXPECT_EQ(m.discrepancies->mirror_aware_m, d->mirror_aware_m);
        }
    }
}

}  // namespace
}  // namespace squint::obstacles
