// The robot's own reflection (explore/mirror_watch.hpp) on constructed sonar scans: the base of a
// disc cast column by column, standing still or standing where the robot's position mirrored in a
// plane puts it.
#include "squint/explore/mirror_watch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/explore/obstacle_memory.hpp"

namespace squint::explore {
namespace {

constexpr double kBody = 0.25;  // the robot's radius

// A 64-column scan over ±27.5° (left to right, left positive) from `robot`: columns whose ray
// meets the disc of `radius` around `centre` read its near side as a boundary, the others floor
// far beyond (5 m).
std::vector<SonarColumn> DiscScan(const Pose2& robot, const Eigen::Vector2d& centre, double radius) {
  const int n = 64;
  const double half = DegToRad(27.5);
  std::vector<SonarColumn> scan(n);
  const Eigen::Vector2d o = robot.Translation();
  for (int i = 0; i < n; ++i) {
    SonarColumn& c = scan[static_cast<std::size_t>(i)];
    c.bearing_rad = half - 2.0 * half * i / (n - 1);
    const double yaw = robot.yaw + c.bearing_rad;
    const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
    const Eigen::Vector2d q = centre - o;
    const double along = q.dot(d);
    const double h2 = q.squaredNorm() - along * along;
    if (along > 0.0 && h2 < radius * radius) {
      c.kind = SonarReturn::kBoundary;
      c.range_m = along - std::sqrt(radius * radius - h2);
    } else {
      c.kind = SonarReturn::kFar;
      c.range_m = 5.0;
    }
    c.own_range_m = c.range_m;
  }
  return scan;
}

// The robot's position mirrored in the plane x = plane_x.
Eigen::Vector2d Reflection(const Pose2& robot, double plane_x) { return {2.0 * plane_x - robot.x, robot.y}; }

TEST(MirrorWatch, ADiscOfTheBodysRadiusIsACandidateAndAWallOrAWiderThingIsNot) {
  const MirrorWatchOptions opt;
  const Pose2 robot{1.0, 0.5, DegToRad(20.0)};
  const double yaw = robot.yaw + DegToRad(-8.0);
  const Eigen::Vector2d centre = robot.Translation() + 1.9 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  const std::vector<Eigen::Vector2d> found = MirrorWatch::Candidates(DiscScan(robot, centre, kBody), robot, opt);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT((found[0] - centre).norm(), 0.03);
  // A disc 0.6 m across its radius spans too many columns; one too far is not looked at.
  EXPECT_TRUE(MirrorWatch::Candidates(DiscScan(robot, centre, 0.6), robot, opt).empty());
  const Eigen::Vector2d far = robot.Translation() + 3.2 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  EXPECT_TRUE(MirrorWatch::Candidates(DiscScan(robot, far, kBody), robot, opt).empty());
  // A wall across the view: every column a boundary, one run as wide as the view.
  std::vector<SonarColumn> wall = DiscScan(robot, centre, kBody);
  for (SonarColumn& c : wall) {
    c.kind = SonarReturn::kBoundary;
    c.range_m = 1.5 / std::cos(c.bearing_rad);
  }
  EXPECT_TRUE(MirrorWatch::Candidates(wall, robot, opt).empty());
  // A disc cut by the view's edge shows part of its arc only.
  const double edge = robot.yaw + DegToRad(27.0);
  const Eigen::Vector2d cut = robot.Translation() + 1.9 * Eigen::Vector2d(std::cos(edge), std::sin(edge));
  EXPECT_TRUE(MirrorWatch::Candidates(DiscScan(robot, cut, kBody), robot, opt).empty());
  // ...and so does one with something nearer beside it.
  std::vector<SonarColumn> hidden = DiscScan(robot, centre, kBody);
  for (std::size_t i = 1; i < hidden.size(); ++i)
    if (hidden[i].kind == SonarReturn::kBoundary && hidden[i - 1].kind != SonarReturn::kBoundary) {
      hidden[i - 1].kind = SonarReturn::kBlockedNear;
      hidden[i - 1].range_m = 0.0;
      break;
    }
  EXPECT_TRUE(MirrorWatch::Candidates(hidden, robot, opt).empty());
}

// The robot drives at `yaw_deg` toward a mirror across x = 3, 5 cm per scan (0.5 m/s at 10 Hz)
// from x = 0.9. Returns the scan index that found the mirror (-1: none) and the mirror.
int Approach(double yaw_deg, double y0, bool reflection, Mirror* mirror) {
  MirrorWatch watch;
  const double yaw = DegToRad(yaw_deg);
  const Eigen::Vector2d still(3.6, 0.1);  // a thing standing, as far as the reflection starts
  for (int i = 0; i < 30; ++i) {
    const Pose2 robot{0.9 + 0.05 * i * std::cos(yaw), y0 + 0.05 * i * std::sin(yaw), yaw};
    if (robot.x > 2.6) break;
    const Eigen::Vector2d centre = reflection ? Reflection(robot, 3.0) : still;
    if (watch.Update(DiscScan(robot, centre, kBody), robot, 0.1 * i)) {
      *mirror = watch.Latest();
      return i;
    }
  }
  return -1;
}

TEST(MirrorWatch, TheRobotsReflectionGivesTheMirrorsPlane) {
  for (double yaw_deg : {0.0, 12.0, -18.0}) {
    SCOPED_TRACE(yaw_deg);
    Mirror m;
    const int at = Approach(yaw_deg, 0.2, true, &m);
    ASSERT_GE(at, 0);
    EXPECT_TRUE(m.found);
    EXPECT_NEAR(m.point.x(), 3.0, 0.03);
    EXPECT_NEAR(RadToDeg(std::atan2(m.normal.y(), m.normal.x())), 0.0, 1.5);
    EXPECT_GE(m.matches, MirrorWatchOptions{}.min_matches);
    // Found while the robot's disc is still well clear of the mirror.
    EXPECT_LT(0.9 + 0.05 * at * std::cos(DegToRad(yaw_deg)), 3.0 - kBody - 0.5);
  }
}

TEST(MirrorWatch, AThingStandingStillIsNoReflection) {
  for (double yaw_deg : {0.0, 12.0, -18.0}) {
    SCOPED_TRACE(yaw_deg);
    Mirror m;
    EXPECT_EQ(Approach(yaw_deg, 0.2, false, &m), -1);
  }
  // It is a candidate all the same, on every scan it is fully in view and near enough.
  const Pose2 robot{1.5, 0.2, 0.0};
  EXPECT_EQ(MirrorWatch::Candidates(DiscScan(robot, {3.6, 0.1}, kBody), robot, {}).size(), 1u);
}

TEST(MirrorWatch, ARobotStandingStillLearnsNothing) {
  MirrorWatch watch;
  const Pose2 robot{1.2, 0.0, 0.0};
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(watch.Update(DiscScan(robot, Reflection(robot, 3.0), kBody), robot, 0.1 * i));
  EXPECT_EQ(watch.Found(), 0);
}

// The obstacle course, start 5 of seed 3: the robot stood still a second looking at a column,
// then drove 0.47 m and a stray candidate (a blip of the sonar's ranges) lay exactly where the
// column would be the robot's reflection in the plane that the blip implies. Ten scans from one
// place are one observation, not ten.
TEST(MirrorWatch, ScansFromOnePlaceCountOnce) {
  const Pose2 a{0.93, -0.20, DegToRad(75.0)};
  const Pose2 b{1.19, 0.19, DegToRad(76.0)};
  const Eigen::Vector2d blip(1.45, 1.22);
  const Eigen::Vector2d n = (blip - b.Translation()).normalized();
  const Eigen::Vector2d mid = 0.5 * (b.Translation() + blip);
  const Eigen::Vector2d column = a.Translation() + 2.0 * (mid - a.Translation()).dot(n) * n;  // a's reflection
  auto found = [&](double distinct_m) {
    MirrorWatchOptions opt;
    opt.distinct_m = distinct_m;
    MirrorWatch watch(opt);
    for (int i = 0; i < 10; ++i) EXPECT_FALSE(watch.Update(DiscScan(a, column, kBody), a, 0.1 * i));
    return watch.Update(DiscScan(b, blip, kBody), b, 1.0);
  };
  EXPECT_TRUE(found(0.0));  // the case as it was found
  EXPECT_FALSE(found(MirrorWatchOptions{}.distinct_m));
}

// The obstacle course, start 0 of seed 20 (and start 3 of seed 12): the robot drives toward a
// thing standing 1.5 m ahead, seen at A on every scan, and on the last scan the sonar's range for
// it jumps 0.3 m nearer, to B. Three of the earlier scans, 0.25-0.35 m back, saw A where the
// plane between the robot and B would have shown the robot's reflection then. But the scan
// before the last saw A, 0.3 m from B after 0.05 m of travel: no reflection moves so.
TEST(MirrorWatch, AReflectionDoesNotJump) {
  const int n = 10;
  auto at = [](int i) { return Pose2{0.9 + 0.05 * i, 0.0, 0.0}; };
  const Eigen::Vector2d b = at(n).Translation() + Eigen::Vector2d(1.2, 0.1);
  const Eigen::Vector2d nrm = (b - at(n).Translation()).normalized();
  const Eigen::Vector2d mid = 0.5 * (at(n).Translation() + b);
  const Eigen::Vector2d from = at(n - 6).Translation();
  const Eigen::Vector2d a = from + 2.0 * (mid - from).dot(nrm) * nrm;  // 6 scans back, the reflection there
  ASSERT_NEAR((a - b).norm(), 0.3, 1e-9);
  auto found = [&](bool continuity) {
    MirrorWatchOptions opt;
    opt.continuity = continuity;
    MirrorWatch watch(opt);
    for (int i = 0; i < n; ++i) EXPECT_FALSE(watch.Update(DiscScan(at(i), a, kBody), at(i), 0.1 * i));
    return watch.Update(DiscScan(at(n), b, kBody), at(n), 0.1 * n);
  };
  EXPECT_TRUE(found(false));  // the case as it was found
  EXPECT_TRUE(MirrorWatchOptions{}.continuity);
  EXPECT_FALSE(found(true));
}

TEST(MirrorWatch, BadOptionsAreNamed) {
  MirrorWatchOptions o;
  EXPECT_EQ(o.Validate(), "");
  o.match_m = 0.6 * o.discriminate_m;
  EXPECT_NE(o.Validate().find("match_m"), std::string::npos);
  o = {};
  o.discriminate_m = o.min_baseline_m + 0.1;
  EXPECT_NE(o.Validate().find("discriminate_m"), std::string::npos);
  o = {};
  o.body_radius_m = 0.0;
  EXPECT_NE(o.Validate().find("body_radius_m"), std::string::npos);
  o = {};
  o.width_tolerance = 1.0;
  EXPECT_NE(o.Validate().find("width_tolerance"), std::string::npos);
}

// A confirmed point stays where floor is later seen beyond it (a mirror shows floor there); an
// ordinary boundary point goes.
TEST(ObstacleMemory, AConfirmedPointOutlastsTheFloorSeenThroughIt) {
  auto free_after_floor_seen = [](bool confirmed) {
    ObstacleMemory mem;
    std::vector<SonarColumn> wall = DiscScan(Pose2{}, {100.0, 0.0}, kBody);
    for (SonarColumn& c : wall) {
      c.kind = SonarReturn::kBoundary;
      c.range_m = 2.0 / std::cos(c.bearing_rad);
    }
    if (confirmed)
      for (double y = -1.0; y <= 1.0; y += 0.05) mem.InsertConfirmed({2.0, y}, 0.0);
    else
      mem.Update(wall, Pose2{}, 0.0, 1.2);
    std::vector<SonarColumn> floor = DiscScan(Pose2{}, {100.0, 0.0}, kBody);  // floor to 5 m everywhere
    mem.Update(floor, Pose2{}, 0.1, 1.2);
    mem.Gather(Pose2{}, 0.1);
    return mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0);
  };
  EXPECT_NEAR(free_after_floor_seen(true), 2.0 - 0.35, 0.01);
  EXPECT_EQ(free_after_floor_seen(false), 5.0);
}

}  // namespace
}  // namespace squint::explore
