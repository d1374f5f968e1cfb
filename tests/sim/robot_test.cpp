// Robot kinematics, collisions and odometry; protocol schedules.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/sim/ground_truth.hpp"
#include "squint/sim/protocols.hpp"
#include "squint/sim/robot.hpp"

namespace squint::sim {
namespace {

World Corridor20() {
  return ParseWorld(
      "format: squint-world/1\ncorridors: [{from: [0, 0], to: [20, 0], width_m: 2}]\n"
      "robot: {radius_m: 0.25, max_speed_mps: 1.0, max_turn_rate_dps: 90, start: [1, 0, 0]}\n",
      "c20.yaml");
}

TEST(Robot, UnicycleArc) {
  const World w = Corridor20();
  RobotOptions o;
  o.odometry.trans_noise_frac = o.odometry.rot_noise_frac = o.odometry.drift_rad_per_m = 0;
  Robot r(w, {5, -0.5, 0}, o);
  // v = 0.5 m/s, w = 0.5 rad/s for 1 s: a quarter... an arc of radius 1 through 0.5 rad.
  for (int i = 0; i < 30; ++i) ASSERT_FALSE(r.Step(0.5, 0.5).collided);
  EXPECT_NEAR(r.TruePose().x, 5 + std::sin(0.5), 1e-9);
  EXPECT_NEAR(r.TruePose().y, -0.5 + 1 - std::cos(0.5), 1e-9);
  EXPECT_NEAR(r.TruePose().yaw, 0.5, 1e-9);
  // Noise-free odometry equals the true motion in the start frame.
  const Pose2 rel = Between(Pose2{5, -0.5, 0}, r.TruePose());
  EXPECT_NEAR(r.OdomPose().x, rel.x, 1e-9);
  EXPECT_NEAR(r.OdomPose().y, rel.y, 1e-9);
  EXPECT_NEAR(r.OdomPose().yaw, rel.yaw, 1e-9);
}

TEST(Robot, SpeedLimitsClip) {
  const World w = Corridor20();
  Robot r(w, {5, 0, 0});
  r.Step(10.0, 0.0);
  EXPECT_NEAR(r.TruePose().x, 5 + 1.0 / 30, 1e-9);
}

TEST(Robot, StopsAtTheEndWallAndCountsCollisions) {
  const World w = Corridor20();
  Robot r(w, {15, 0, 0});
  int collisions = 0;
  for (int i = 0; i < 300; ++i) collisions += r.Step(1.0, 0.0).collided;
  EXPECT_GT(collisions, 0);
  EXPECT_EQ(r.Collisions(), collisions);
  // The end wall is at x = 21: the robot's disc never crosses it.
  EXPECT_LE(r.TruePose().x, 21 - 0.25 + 1e-12);
  EXPECT_GT(r.TruePose().x, 21 - 0.25 - 1.0 / 30 / 4 - 1e-9);
}

TEST(Robot, HitsObstaclesByName) {
  const World w = ParseWorld(
      "format: squint-world/1\ncorridors: [{from: [0, 0], to: [20, 0], width_m: 3}]\n"
      "obstacles: [{type: bin, at: [6, 0]}]\n",
      "bin.yaml");
  Robot r(w, {4, 0, 0});
  StepResult last;
  for (int i = 0; i < 200 && !last.collided; ++i) last = r.Step(0.5, 0.0);
  ASSERT_TRUE(last.collided);
  EXPECT_NE(last.hit.find("obstacles[0] (bin)"), std::string::npos);
  EXPECT_NEAR(r.TruePose().x, 6 - 0.17 - 0.25, 0.5 / 30);
}

TEST(Robot, StartInsideAWallIsAnError) {
  const World w = Corridor20();
  EXPECT_THROW(Robot(w, {5, 0.9, 0}), Error);
}

TEST(Odometry, NoisyButDeterministicPerSeed) {
  OdometryOptions o;
  o.trans_noise_frac = 0.05;
  o.rot_noise_frac = 0.05;
  o.drift_rad_per_m = 0.01;
  Odometry a(o), b(o);
  a.Reset({0, 0, 0});
  b.Reset({0, 0, 0});
  for (int i = 1; i <= 100; ++i) {
    const Pose2 p{0.1 * i, 0.0, 0.0};
    a.Update(p);
    b.Update(p);
  }
  EXPECT_EQ(a.Pose().x, b.Pose().x);
  EXPECT_EQ(a.Pose().yaw, b.Pose().yaw);
  EXPECT_GT(std::abs(a.Pose().x - 10.0) + std::abs(a.Pose().yaw), 1e-4);
  // Drift dominates the yaw over 10 m: about +0.1 rad.
  EXPECT_NEAR(a.Pose().yaw, 0.1, 0.05);
}

TEST(Protocols, SweepStationsAndHeadings) {
  const World w = LoadWorld("corridor-0");
  const auto s = SweepSchedule(w, SweepOptions{});
  ASSERT_EQ(s.size() % 41, 0u);
  EXPECT_GE(s.size() / 41, 6u);  // 30 m corridor, one station every 4.572 m
  for (std::size_t i = 0; i < 41; ++i)
    EXPECT_NEAR(*GroundTruthAt(w, s[i].pose).heading_deg, -20.0 + static_cast<double>(i), 1e-9);
  EXPECT_NEAR((s[41].pose.Translation() - s[0].pose.Translation()).norm(), 4.572, 1e-9);
  for (std::size_t i = 1; i < s.size(); ++i) EXPECT_GT(s[i].stamp, s[i - 1].stamp);
}

TEST(Protocols, DriveThreePassesStopBeforeTheEnd) {
  const World w = LoadWorld("corridor-0");
  const auto d = DriveSchedule(w, DriveOptions{});
  double min_dist = 1e9;
  std::set<long> laterals;
  for (const auto& tp : d) {
    const GroundTruth gt = GroundTruthAt(w, tp.pose);
    min_dist = std::min(min_dist, *gt.dist_end_m);
    laterals.insert(std::lround(*gt.lateral_m * 100));
    EXPECT_NEAR(*gt.heading_deg, 0.0, 1e-9);
  }
  EXPECT_EQ(laterals, (std::set<long>{-45, 0, 45}));
  EXPECT_GE(min_dist, 0.5 - 1e-9);
  EXPECT_LT(min_dist, 0.5 + 0.4 / 30 + 1e-9);
  EXPECT_NEAR(d[1].stamp - d[0].stamp, 1.0 / 30, 1e-12);
  EXPECT_NEAR(d[1].pose.x - d[0].pose.x, 0.4 / 30, 1e-12);
}

TEST(Protocols, CreepStepsAroundObstaclesWithoutCollision) {
  const World w = LoadWorld("obstacle-course");
  const auto c = CreepSchedule(w, CreepOptions{});
  ASSERT_GT(c.size(), 200u);
  Robot probe(w, w.start);
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_TRUE(probe.IsFreePose(c[i].pose.Translation())) << i;
    if (i > 0) {
      EXPECT_NEAR((c[i].pose.Translation() - c[i - 1].pose.Translation()).norm(), 0.031, 0.002) << i;
      EXPECT_NEAR(c[i].stamp - c[i - 1].stamp, 0.77, 1e-12);
    }
  }
}

}  // namespace
}  // namespace squint::sim
