// Known-answer tests of the camera model: bearings, floor intersection, projection round trips.
#include <gtest/gtest.h>

#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/camera.hpp"
#include "squint/core/pose.hpp"

namespace squint {
namespace {

CameraModel Cam(double pitch_deg, std::vector<double> dist = {}) {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 176.0;
  c.cx = 79.5;
  c.cy = 59.5;
  c.height_m = 0.7;
  c.pitch_deg = pitch_deg;
  c.distortion = std::move(dist);
  return c;
}

TEST(CameraModel, BearingIsLeftPositive) {
  const CameraModel c = Cam(0.0);
  EXPECT_DOUBLE_EQ(c.BearingOfColumn(c.cx), 0.0);
  EXPECT_NEAR(c.BearingOfColumn(c.cx - c.fx), kPi / 4, 1e-12);  // left of centre: positive
  EXPECT_NEAR(c.HeadingFromColumn(c.cx + c.fx), kPi / 4, 1e-12);
}

TEST(CameraModel, CentreRayOfLevelCameraLooksForward) {
  const Eigen::Vector3d d = Cam(0.0).PixelRayRobot({79.5, 59.5});
  EXPECT_NEAR(d.x(), 1.0, 1e-12);
  EXPECT_NEAR(d.y(), 0.0, 1e-12);
  EXPECT_NEAR(d.z(), 0.0, 1e-12);
  EXPECT_FALSE(Cam(0.0).FloorPoint({79.5, 59.5}).has_value());  // on the horizon
}

TEST(CameraModel, FloorPointAtAnalyticDistance) {
  // A level camera h above the floor: the row v sees the floor at x = h * fy / (v - cy).
  const CameraModel c = Cam(0.0);
  const double v = 59.5 + 40.0;
  const auto p = c.FloorPoint({79.5, v});
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->x(), 0.7 * 176.0 / 40.0, 1e-9);
  EXPECT_NEAR(p->y(), 0.0, 1e-12);
  // Pitched down by p: the image centre sees the floor at h / tan(|p|).
  const CameraModel pitched = Cam(-10.0);
  const auto q = pitched.FloorPoint({79.5, 59.5});
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->x(), 0.7 / std::tan(DegToRad(10.0)), 1e-9);
}

TEST(CameraModel, HorizonRowMatchesRayGeometry) {
  const CameraModel c = Cam(-8.0);
  const double v = c.HorizonRow();
  EXPECT_NEAR(c.PixelRayRobot({79.5, v}).z(), 0.0, 1e-12);
  EXPECT_LT(v, c.cy);  // looking down puts the horizon above the centre
}

TEST(CameraModel, ProjectInvertsFloorPointWithDistortion) {
  const CameraModel c = Cam(-6.0, {-0.2, 0.05, 0.001, -0.002, 0.0});
  for (double u : {5.0, 40.0, 79.5, 130.0, 155.0})
    for (double v : {70.0, 90.0, 118.0}) {
      const auto p = c.FloorPoint({u, v});
      ASSERT_TRUE(p.has_value());
      const auto back = c.Project({p->x(), p->y(), 0.0});
      ASSERT_TRUE(back.has_value());
      EXPECT_NEAR(back->x(), u, 1e-6);
      EXPECT_NEAR(back->y(), v, 1e-6);
    }
}

TEST(CameraModel, ScaledKeepsPixelCentreConvention) {
  const CameraModel g = Cam(0.0).Scaled(32, 24);
  EXPECT_DOUBLE_EQ(g.cx, 15.5);
  EXPECT_DOUBLE_EQ(g.cy, 11.5);
  EXPECT_DOUBLE_EQ(g.fx, 176.0 / 5.0);
}

TEST(CameraModel, ValidateNamesProblems) {
  CameraModel c = Cam(0.0);
  EXPECT_EQ(c.Validate(), "");
  c.fx = 0.0;
  EXPECT_NE(c.Validate().find("fx"), std::string::npos);
  c = Cam(0.0, {1.0, 2.0});
  EXPECT_NE(c.Validate().find("distortion"), std::string::npos);
}

TEST(Pose2, ComposeAndInverseRoundTrip) {
  const Pose2 a{1.0, 2.0, 0.5}, b{-0.3, 0.7, -1.2};
  const Pose2 ab = a * b;
  const Pose2 back = Between(a, ab);
  EXPECT_NEAR(back.x, b.x, 1e-12);
  EXPECT_NEAR(back.y, b.y, 1e-12);
  EXPECT_NEAR(back.yaw, b.yaw, 1e-12);
  const Pose2 id = a * a.Inverse();
  EXPECT_NEAR(id.x, 0.0, 1e-12);
  EXPECT_NEAR(id.y, 0.0, 1e-12);
  EXPECT_NEAR(id.yaw, 0.0, 1e-12);
}

TEST(Angles, WrapStaysInRange) {
  EXPECT_NEAR(WrapPi(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(WrapPi(-3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(WrapDeg(370.0), 10.0, 1e-9);
  EXPECT_NEAR(AngleDiff(DegToRad(179.0), DegToRad(-179.0)), DegToRad(-2.0), 1e-12);
}

}  // namespace
}  // namespace squint
