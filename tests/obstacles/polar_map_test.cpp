// Tests of the polar occupancy map: sector assignment, the ROI, the field of view.
#include "squint/obstacles/polar_map.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "avoid_scene.hpp"
#include "squint/core/angles.hpp"

namespace squint::obstacles {
namespace {

ContactPoint At(double range_m, double bearing_deg) {
  ContactPoint c;
  c.range_m = range_m;
  c.bearing_deg = bearing_deg;
  c.floor_m = range_m * Eigen::Vector2d(std::cos(DegToRad(bearing_deg)), std::sin(DegToRad(bearing_deg)));
  return c;
}

TEST(PolarMapTest, SectorsCoverTheSemicircleRightToLeft) {
  PolarMapper m(testing::ObstacleCamera());
  const PolarMap& map = m.Map();
  ASSERT_EQ(map.sectors.size(), 36u);
  EXPECT_DOUBLE_EQ(map.sectors.front().start_deg, -90.0);
  EXPECT_DOUBLE_EQ(map.sectors.back().end_deg, 90.0);
  EXPECT_DOUBLE_EQ(map.sectors[18].centre_deg, 2.5);
  EXPECT_EQ(*m.SectorOf(0.0), 18);
  EXPECT_EQ(*m.SectorOf(-0.1), 17);
  EXPECT_EQ(*m.SectorOf(90.0), 35);
  EXPECT_FALSE(m.SectorOf(120.0).has_value());
}

TEST(PolarMapTest, InViewFollowsTheFieldOfView) {
  const CameraModel cam = testing::ObstacleCamera();
  PolarMapper m(cam);
  // Half the horizontal field of view is atan(128 / 194.7) = 33.3°; the bearing of the image
  // edge on the floor at 1.5 m is a little smaller because the camera looks down.
  const double half_fov = RadToDeg(std::atan(128.0 / cam.fx));
  for (const PolarSector& s : m.Map().sectors) {
    if (std::max(std::abs(s.start_deg), std::abs(s.end_deg)) <= 25.0) {
      EXPECT_TRUE(s.in_view) << s.centre_deg;
    }
    if (std::max(std::abs(s.start_deg), std::abs(s.end_deg)) > half_fov) {
      EXPECT_FALSE(s.in_view) << s.centre_deg;
    }
  }
}

TEST(PolarMapTest, ContactsInsideTheRoiOccupyTheirSectors) {
  PolarMapper m(testing::ObstacleCamera());
  std::vector<ContactPoint> c = {At(1.0, 12.0), At(0.8, 13.0), At(2.0, -7.0), At(1.2, 60.0)};
  const PolarMap& map = m.Build(c);
  const PolarSector& s12 = map.sectors[*m.SectorOf(12.0)];
  EXPECT_EQ(s12.state, SectorState::kOccupied);
  EXPECT_EQ(s12.contacts, 2);
  EXPECT_DOUBLE_EQ(*s12.range_m, 0.8);
  // Beyond the ROI: free, but the scan reading keeps it.
  const PolarSector& s7 = map.sectors[*m.SectorOf(-7.0)];
  EXPECT_EQ(s7.state, SectorState::kFree);
  EXPECT_FALSE(s7.range_m.has_value());
  EXPECT_DOUBLE_EQ(*s7.nearest_m, 2.0);
  // A contact outside the field of view still occupies its sector.
  EXPECT_EQ(map.sectors[*m.SectorOf(60.0)].state, SectorState::kOccupied);
  EXPECT_EQ(map.sectors[*m.SectorOf(75.0)].state, SectorState::kUnseen);
  EXPECT_EQ(map.sectors[*m.SectorOf(0.0)].state, SectorState::kFree);
  // A second build starts afresh.
  const PolarMap& empty = m.Build({});
  EXPECT_EQ(empty.sectors[*m.SectorOf(12.0)].state, SectorState::kFree);
  EXPECT_FALSE(empty.sectors[*m.SectorOf(-7.0)].nearest_m.has_value());
}

TEST(PolarMapTest, MinContactsSetsTheHistogramThreshold) {
  PolarMapOptions o;
  o.min_contacts = 2;
  PolarMapper m(testing::ObstacleCamera(), o);
  const PolarMap& map = m.Build(std::vector<ContactPoint>{At(1.0, 12.0), At(1.1, -12.0), At(1.2, -12.5)});
  EXPECT_EQ(map.sectors[*m.SectorOf(12.0)].state, SectorState::kFree);
  EXPECT_EQ(map.sectors[*m.SectorOf(-12.0)].state, SectorState::kOccupied);
}

TEST(PolarMapTest, FreeNeedsGroundEvidenceWhenAsked) {
  PolarMapOptions o;
  o.free_needs_ground = true;
  PolarMapper m(testing::ObstacleCamera(), o);
  const std::vector<Eigen::Vector2d> ground = {{1.0, 0.0}, {1.0, 0.01}, {2.0, -0.1}, {0.9, -0.2}};
  const PolarMap& map = m.Build(std::vector<ContactPoint>{At(1.0, 12.0)}, ground);
  EXPECT_EQ(map.sectors[*m.SectorOf(0.3)].state, SectorState::kFree);
  EXPECT_EQ(map.sectors[*m.SectorOf(0.3)].ground, 2);
  EXPECT_EQ(map.sectors[*m.SectorOf(-12.5)].state, SectorState::kFree);
  // (2.0, -0.1) is beyond the ROI: no evidence for its sector.
  EXPECT_EQ(map.sectors[*m.SectorOf(-2.9)].state, SectorState::kUnseen);
  EXPECT_EQ(map.sectors[*m.SectorOf(12.0)].state, SectorState::kOccupied);
  EXPECT_EQ(map.sectors[*m.SectorOf(20.0)].state, SectorState::kUnseen);
  // Evidence nearer than min_ground_range_m does not count: (0.9, -0.2) is 0.92 m away.
  o.min_ground_range_m = 0.95;
  PolarMapper far(testing::ObstacleCamera(), o);
  const PolarMap& fm = far.Build(std::vector<ContactPoint>{}, ground);
  EXPECT_EQ(fm.sectors[*far.SectorOf(-12.5)].state, SectorState::kUnseen);
  EXPECT_EQ(fm.sectors[*far.SectorOf(0.3)].state, SectorState::kFree);
}

TEST(PolarMapTest, OptionsMustDivideTheSemicircle) {
  PolarMapOptions o;
  o.sector_deg = 7.0;
  EXPECT_NE(o.Validate().find("sector_deg"), std::string::npos);
  o.sector_deg = 4.5;
  EXPECT_TRUE(o.Validate().empty());
  o.roi_radius_m = -1;
  EXPECT_NE(o.Validate().find("roi_radius_m"), std::string::npos);
}

}  // namespace
}  // namespace squint::obstacles
