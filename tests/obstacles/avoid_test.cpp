// End-to-end tests of the Avoider on ray-cast scenes: a box ahead makes the robot steer around
// it; a wall of boxes makes it stop; options are checked.
#include "squint/obstacles/avoider.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "avoid_scene.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::obstacles {
namespace {

using testing::Box;
using testing::Feature;
using testing::ObstacleCamera;
using testing::RenderBoxes;

// Obstacle features along the vertical edges of a box's front face, ground features on the floor
// in front of it.
std::vector<ClassifiedFeature> BoxFeatures(const CameraModel& cam, const Box& b) {
  std::vector<ClassifiedFeature> f;
  for (double y : {b.y_right_m, b.y_left_m}) {
    f.push_back(Feature(cam, {b.x_near_m, y, 0.5 * b.height_m}, FeatureClass::kObstacle));
    f.push_back(Feature(cam, {b.x_near_m - 0.3, y, 0.0}, FeatureClass::kGround));
  }
  return f;
}

// The lateral distance of the floor point (x, y) from the ray at `steer_deg`.
double Clearance(double x, double y, double steer_deg) {
  const double a = DegToRad(steer_deg);
  return std::abs(-std::sin(a) * x + std::cos(a) * y);
}

TEST(AvoidTest, BoxAheadIsAvoided) {
  const CameraModel cam = ObstacleCamera();
  // A box a little left of straight ahead: its front corners are at bearings 4.4° and 21.0°.
  const Box box{1.3, 1.6, 0.1, 0.5, 0.3};
  Avoider avoider(cam);
  const AvoidResult& r = avoider.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box));
  ASSERT_EQ(r.traces->size(), 2u) << "one outline per vertical edge";
  ASSERT_GT(r.contacts.size(), 20u) << "and the base between them";
  // The sectors across the box's front (4.4° to 21.0°) are occupied, those clear of it are not.
  for (const PolarSector& s : r.map->sectors) {
    if (s.end_deg > 4.4 + 0.5 && s.start_deg < 21.0 - 0.5) {
      EXPECT_EQ(s.state, SectorState::kOccupied) << s.centre_deg;
    } else if (s.end_deg < 4.4 - 1.0 || s.start_deg > 21.0 + 1.0) {
      EXPECT_NE(s.state, SectorState::kOccupied) << s.centre_deg;
    }
  }
  ASSERT_FALSE(r.decision.stop);
  // The steering ray passes both true corners with at least the robot's half width plus margin.
  const double half = avoider.Options().gap.robot_radius_m + avoider.Options().gap.margin_m;
  EXPECT_LT(*r.decision.steer_deg, 0.0) << "turns right, away from the box";
  EXPECT_GE(Clearance(1.3, 0.1, *r.decision.steer_deg), half);
  EXPECT_GE(Clearance(1.3, 0.5, *r.decision.steer_deg), half);
  // Deterministic: the same input gives the same output.
  const double first = *r.decision.steer_deg;
  const AvoidResult& again = avoider.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box));
  EXPECT_DOUBLE_EQ(*again.decision.steer_deg, first);
}

TEST(AvoidTest, WithoutBaseTracingOnlyTheCornersAreOccupied) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.3, 1.6, 0.1, 0.5, 0.3};
  AvoidOptions o;
  o.outline.base_trace = false;
  Avoider avoider(cam, o);
  const AvoidResult& r = avoider.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box));
  ASSERT_EQ(r.contacts.size(), 2u);  // the paper's map: the two front corners
  int occupied = 0;
  for (const PolarSector& s : r.map->sectors) occupied += s.state == SectorState::kOccupied;
  EXPECT_EQ(occupied, 2);
}

TEST(AvoidTest, EmptyFloorSteersStraight) {
  const CameraModel cam = ObstacleCamera();
  Avoider avoider(cam);
  const AvoidResult& r = avoider.Process(RenderBoxes(cam, {}), {});
  ASSERT_FALSE(r.decision.stop);
  EXPECT_NEAR(*r.decision.steer_deg, 0.0, 2.5) << "the centre of the symmetric field of view";
}

TEST(AvoidTest, WallOfBoxesStops) {
  const CameraModel cam = ObstacleCamera();
  // Boxes 0.3 m wide with 0.2 m gaps, 0.9 m ahead, across the whole view: no gap fits a 0.6 m
  // robot.
  std::vector<Box> boxes;
  std::vector<ClassifiedFeature> f;
  // Thin plates, so that the front corners are the silhouettes seen from any side.
  for (double y = -1.2; y < 1.2; y += 0.5) {
    const Box b{0.9, 0.92, y, y + 0.3, 0.4};
    boxes.push_back(b);
    for (auto& x : BoxFeatures(cam, b)) f.push_back(x);
  }
  Avoider avoider(cam);
  const AvoidResult& r = avoider.Process(RenderBoxes(cam, boxes), f);
  EXPECT_TRUE(r.decision.stop);
  EXPECT_FALSE(r.decision.steer_deg.has_value());
  EXPECT_GE(r.contacts.size(), 4u);
}

TEST(AvoidTest, InvalidOptionsOrCameraThrow) {
  AvoidOptions o;
  o.polar.sector_deg = 7.0;
  EXPECT_THROW(Avoider(ObstacleCamera(), o), Error);
  CameraModel no_intrinsics = ObstacleCamera();
  no_intrinsics.fx = 0;
  EXPECT_THROW(Avoider(no_intrinsics, {}), Error);
}

// The contact memory: the box of BoxAheadIsAvoided seen from the odometry origin, then an empty
// view after the robot turned 60° right in place, so that the box lies left of the 65° view.
TEST(AvoidTest, ContactMemoryKeepsEarlierContactsInTheOdometryFrame) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.3, 1.6, 0.1, 0.5, 0.3};
  AvoidOptions o;
  o.memory.decisions = 2;
  Avoider avoider(cam, o);
  const Pose2 origin{0.0, 0.0, 0.0};
  const AvoidResult& first = avoider.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box), origin);
  EXPECT_TRUE(first.remembered.empty()) << "nothing seen before";
  std::vector<Eigen::Vector2d> seen;
  for (const ContactPoint& c : first.contacts)
    if (c.range_m <= o.polar.roi_radius_m) seen.push_back(c.floor_m);
  ASSERT_GT(seen.size(), 20u);

  const Pose2 turned{0.0, 0.0, DegToRad(-60.0)};
  const cv::Mat empty = RenderBoxes(cam, {});
  const AvoidResult& r = avoider.Process(empty, {}, turned);
  EXPECT_TRUE(r.contacts.empty());
  ASSERT_EQ(r.remembered.size(), seen.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    // In the turned robot frame a point p of the old frame is R(+60°) p.
    const double c = std::cos(DegToRad(60.0)), s = std::sin(DegToRad(60.0));
    const Eigen::Vector2d expected(c * seen[i].x() - s * seen[i].y(), s * seen[i].x() + c * seen[i].y());
    EXPECT_NEAR((r.remembered[i].floor_m - expected).norm(), 0.0, 1e-9);
    EXPECT_NEAR(r.remembered[i].range_m, seen[i].norm(), 1e-9);
    EXPECT_NEAR(r.remembered[i].bearing_deg, RadToDeg(std::atan2(seen[i].y(), seen[i].x())) + 60.0, 1e-9);
    EXPECT_TRUE(std::isnan(r.remembered[i].pixel.x()));
  }
  // The box's front (bearings 4.4° to 21.0° before) is now at 64.4° to 81.0°, out of view, and
  // its sectors are occupied from memory.
  for (const PolarSector& s : r.map->sectors) {
    if (s.end_deg > 64.4 + 0.5 && s.start_deg < 81.0 - 0.5) {
      EXPECT_EQ(s.state, SectorState::kOccupied) << s.centre_deg;
    } else if (s.end_deg < 64.4 - 1.0 || s.start_deg > 81.0 + 1.0) {
      EXPECT_NE(s.state, SectorState::kOccupied) << s.centre_deg;
    }
  }
  // The same view without the pose: no memory, nothing occupied.
  const AvoidResult& plain = avoider.Process(empty, {});
  EXPECT_TRUE(plain.remembered.empty());
  for (const PolarSector& s : plain.map->sectors) EXPECT_NE(s.state, SectorState::kOccupied);
  // memory.decisions = 2: the box's contacts serve the two decisions after the one that saw them.
  EXPECT_EQ(avoider.Process(empty, {}, turned).remembered.size(), seen.size());
  EXPECT_TRUE(avoider.Process(empty, {}, turned).remembered.empty());
}

TEST(AvoidTest, StraightPathClearChecksTheFootprintAgainstRememberedContacts) {
  const CameraModel cam = ObstacleCamera();
  // The box's right front corner at (1.3, 0.1): the footprint's half width is 0.25 + 0.05 m.
  const Box box{1.3, 1.6, 0.1, 0.5, 0.3};
  Avoider avoider(cam);
  const Pose2 origin{0.0, 0.0, 0.0};
  avoider.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box), origin);
  EXPECT_TRUE(avoider.StraightPathClear(origin, 0.9)) << "stops 0.4 m short of the box";
  EXPECT_FALSE(avoider.StraightPathClear(origin, 1.5)) << "would drive into it";
  // Moved 0.5 m right (odometry y = -0.5) the box's nearest contact is 0.6 m left of the path.
  EXPECT_TRUE(avoider.StraightPathClear(Pose2{0.0, -0.5, 0.0}, 3.0));
  // Facing away from it, the box is behind.
  EXPECT_TRUE(avoider.StraightPathClear(Pose2{0.0, 0.0, DegToRad(180.0)}, 3.0));
  std::vector<Eigen::Vector2d> points;
  avoider.RememberedPoints(origin, &points);
  EXPECT_GT(points.size(), 20u);
  avoider.ClearMemory();
  EXPECT_TRUE(avoider.StraightPathClear(origin, 1.5));
  // Without the pose nothing is remembered.
  Avoider no_pose(cam);
  no_pose.Process(RenderBoxes(cam, {box}), BoxFeatures(cam, box));
  EXPECT_TRUE(no_pose.StraightPathClear(origin, 1.5));
}

TEST(AvoidTest, InvalidMemoryOptionsThrow) {
  AvoidOptions o;
  o.memory.decisions = -1;
  EXPECT_THROW(Avoider(ObstacleCamera(), o), Error);
  o.memory.decisions = 4;
  o.memory.radius_m = 0.0;
  EXPECT_THROW(Avoider(ObstacleCamera(), o), Error);
}

}  // namespace
}  // namespace squint::obstacles
