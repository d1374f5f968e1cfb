// The obstacle pipeline's advice (polar map + free-gap steering → ObstacleAdvice) on hand-made
// polar maps with known answers, and the explorer's obstacle override on scripted percepts:
// obstacle across the path → steer toward the gap (held between advices), blocked → stop and
// turn (probe), clear → corridor following again.
#include "squint/explore/obstacle_advice.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/explore/explorer.hpp"

namespace squint::explore {
namespace {

// A 5° polar map from −90° to +90°: sectors within ±view_deg are in view and free, the rest
// unseen; Occupy() marks sectors holding a contact at a range.
struct MapBuilder {
  obstacles::PolarMap map;
  explicit MapBuilder(double view_deg = 30.0) {
    map.roi_radius_m = 1.5;
    map.sector_deg = 5.0;
    for (int i = 0; i < 36; ++i) {
      obstacles::PolarSector s;
      s.start_deg = -90.0 + 5.0 * i;
      s.end_deg = s.start_deg + 5.0;
      s.centre_deg = s.start_deg + 2.5;
      s.in_view = s.start_deg >= -view_deg && s.end_deg <= view_deg;
      s.state = s.in_view ? obstacles::SectorState::kFree : obstacles::SectorState::kUnseen;
      map.sectors.push_back(s);
    }
  }
  MapBuilder& Occupy(double from_deg, double to_deg, double range_m) {
    for (obstacles::PolarSector& s : map.sectors) {
      if (s.start_deg >= from_deg - 1e-9 && s.end_deg <= to_deg + 1e-9) {
        s.state = obstacles::SectorState::kOccupied;
        s.contacts = 3;
        s.range_m = range_m;
        s.nearest_m = range_m;
      }
    }
    return *this;
  }
  ObstacleAdvice Advice(double robot_radius_m = 0.25) const {
    obstacles::GapOptions gap;
    gap.robot_radius_m = robot_radius_m;  // margin 0.05: gaps need 0.6 m
    std::vector<obstacles::Gap> gaps;
    obstacles::FindGaps(map, gap, &gaps);
    ObstacleAdviceOptions o;
    o.robot_radius_m = robot_radius_m;  // path half-width 0.35 m
    return MakeObstacleAdvice(map, obstacles::ChooseSteering(gaps), o);
  }
};

TEST(ObstacleAdvice, EmptyMapIsClearAndStraightAhead) {
  const ObstacleAdvice a = MapBuilder().Advice();
  EXPECT_FALSE(a.obstacle_in_roi);
  EXPECT_FALSE(a.in_path);
  EXPECT_TRUE(std::isinf(a.nearest_in_path_m));
  EXPECT_FALSE(a.blocked);
  EXPECT_DOUBLE_EQ(a.steer_deg, 0.0);  // one gap, −30° … +30°
}

TEST(ObstacleAdvice, BoxAheadLeftSteersToTheRightGap) {
  // Occupied 0° … 15° at 1.2 m. Right gap −30° … 0° (centre −15°): clearance to the box's edge
  // 2 · 1.2 · sin 15° = 0.62 m ≥ 0.6 m, passable; left gap 15° … 30° (centre 22.5°): 2 · 1.2 ·
  // sin 7.5° = 0.31 m, too narrow.
  const ObstacleAdvice a = MapBuilder().Occupy(0.0, 15.0, 1.2).Advice();
  EXPECT_TRUE(a.obstacle_in_roi);
  EXPECT_TRUE(a.in_path);
  // Distance ahead (along the heading): the sector 10° … 15° is still in the path (1.2 sin 10° =
  // 0.21 m < 0.35 m) and its contact is 1.2 cos 10° ahead, nearer than 0° … 5°'s 1.2 m.
  EXPECT_NEAR(a.nearest_in_path_m, 1.2 * std::cos(DegToRad(10.0)), 1e-12);
  EXPECT_FALSE(a.blocked);
  EXPECT_DOUBLE_EQ(a.steer_deg, -15.0);
}

TEST(ObstacleAdvice, PathHalfWidthDecidesWhatIsInThePath) {
  // 20° … 25° at 0.9 m: nearest bearing 20°, lateral 0.9 sin 20° = 0.308 m < 0.35 m: in the path,
  // 0.9 cos 20° = 0.846 m ahead.
  const ObstacleAdvice near = MapBuilder().Occupy(20.0, 25.0, 0.9).Advice();
  EXPECT_TRUE(near.in_path);
  EXPECT_NEAR(near.nearest_in_path_m, 0.9 * std::cos(DegToRad(20.0)), 1e-12);
  // −30° … −25° at 1.0 m: lateral 1.0 sin 25° = 0.42 m > 0.35 m: in the ROI, beside the path
  // (a side wall's foot seen at the edge of the view).
  const ObstacleAdvice side = MapBuilder().Occupy(-30.0, -25.0, 1.0).Advice();
  EXPECT_TRUE(side.obstacle_in_roi);
  EXPECT_FALSE(side.in_path);
  EXPECT_FALSE(side.blocked);
  // With a wider robot (0.35 m: half-width 0.45 m) the same contact is in the path.
  EXPECT_TRUE(MapBuilder().Occupy(-30.0, -25.0, 1.0).Advice(0.35).in_path);
}

TEST(ObstacleAdvice, EverythingInViewOccupiedIsBlocked) {
  const ObstacleAdvice a = MapBuilder().Occupy(-30.0, 30.0, 1.0).Advice();
  EXPECT_TRUE(a.in_path);
  EXPECT_TRUE(a.blocked);
  EXPECT_DOUBLE_EQ(a.steer_deg, 0.0);
  // Free sectors left only in narrow slivers (5° at 1.0 m: 2 · sin 2.5° · 1.0 = 0.09 m) are blocked too.
  const ObstacleAdvice b = MapBuilder().Occupy(-30.0, -5.0, 1.0).Occupy(0.0, 30.0, 1.0).Advice();
  EXPECT_TRUE(b.blocked);
}

TEST(ObstacleAdvice, InvalidOptionsAreRejected) {
  ObstacleAdviceOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.path_margin_m = -0.1;
  EXPECT_FALSE(o.Validate().empty());
  o = {};
  o.robot_radius_m = std::nan("");
  EXPECT_FALSE(o.Validate().empty());
}

// --- The explorer's override on scripted percepts -----------------------------------------------

constexpr double kDt = 1.0 / 30.0;

// An endless straight corridor along +x: every frame processed, heading = yaw, centred, no end
// in sight, a corridor's entropy. Ideal odometry.
struct EndlessCorridor {
  Pose2 pose;
  int frame = 0;
  Percept Perceive() const {
    Percept p;
    p.stamp_s = frame * kDt;
    p.odom_T_robot = pose;
    p.processed = true;
    p.heading_deg = RadToDeg(pose.yaw);
    p.centre_heading_deg = RadToDeg(pose.yaw);
    p.dist_end_m = 30.0;
    p.glance_entropy_nats = 3.3;
    return p;
  }
  void Apply(const Command& c) {
    const double mid = pose.yaw + 0.5 * c.omega_rps * kDt;
    pose.x += c.v_mps * kDt * std::cos(mid);
    pose.y += c.v_mps * kDt * std::sin(mid);
    pose.yaw = WrapPi(pose.yaw + c.omega_rps * kDt);
    ++frame;
  }
};

// Steps until the explorer follows the corridor (it aligns first).
void StartFollowing(EndlessCorridor& w, Explorer& e) {
  for (int i = 0; i < 300 && e.State() != ExploreState::kFollow; ++i) w.Apply(e.Step(w.Perceive()));
  ASSERT_EQ(e.State(), ExploreState::kFollow);
  for (int i = 0; i < 30; ++i) w.Apply(e.Step(w.Perceive()));
  ASSERT_NEAR(w.pose.yaw, 0.0, 1e-6);
}

ObstacleAdvice InPath(double steer_deg, bool blocked = false) {
  ObstacleAdvice a;
  a.obstacle_in_roi = a.in_path = true;
  a.nearest_in_path_m = 1.0;
  a.blocked = blocked;
  a.steer_deg = blocked ? 0.0 : steer_deg;
  return a;
}

TEST(ExplorerObstacleOverride, SteersTowardTheGapHoldsItThenFollowsAgain) {
  EndlessCorridor w;
  ExplorerOptions opt;
  opt.avoid_confirm_advices = 1;
  Explorer e(opt);
  StartFollowing(w, e);
  // Obstacle across the path, widest gap 20° to the left.
  Percept p = w.Perceive();
  p.obstacles = InPath(20.0);
  Command c = e.Step(p);
  EXPECT_NEAR(c.omega_rps, std::min(opt.max_omega_rps, opt.avoid_gain * DegToRad(20.0)), 1e-9);
  EXPECT_NEAR(c.v_mps, opt.cruise_speed_mps * opt.avoid_speed_fraction, 1e-12);
  EXPECT_EQ(e.ObstacleOverrides(), 1);
  w.Apply(c);
  // Between advices the gap's direction is held in the odometry frame: ω shrinks as the robot turns.
  double yaw_before = w.pose.yaw;
  for (int i = 0; i < 5; ++i) {
    c = e.Step(w.Perceive());
    EXPECT_NEAR(c.omega_rps, opt.avoid_gain * (DegToRad(20.0) - w.pose.yaw), 1e-9) << i;
    EXPECT_GT(c.omega_rps, 0.0);
    w.Apply(c);
    EXPECT_GT(w.pose.yaw, yaw_before);
    yaw_before = w.pose.yaw;
  }
  // A clear advice hands back to corridor following: it turns back toward the axis at cruise-
  // dependent speed, not the override's.
  p = w.Perceive();
  p.obstacles = ObstacleAdvice{};
  c = e.Step(p);
  EXPECT_LT(c.omega_rps, 0.0);
  EXPECT_EQ(e.ObstacleOverrides(), 6);
  EXPECT_EQ(e.State(), ExploreState::kFollow);
}

TEST(ExplorerObstacleOverride, StaleAdviceAndObstaclesBesideThePathDoNotOverride) {
  EndlessCorridor w;
  ExplorerOptions opt;
  opt.avoid_confirm_advices = 1;
  Explorer e(opt);
  StartFollowing(w, e);
  Percept p = w.Perceive();
  ObstacleAdvice beside;
  beside.obstacle_in_roi = true;  // a wall's foot beside the path
  beside.steer_deg = 25.0;
  p.obstacles = beside;
  Command c = e.Step(p);
  EXPECT_NEAR(c.omega_rps, 0.0, 1e-9);
  EXPECT_NEAR(c.v_mps, opt.cruise_speed_mps, 1e-9);
  w.Apply(c);
  // An in-path advice is dropped once older than avoid_hold_s.
  p = w.Perceive();
  p.obstacles = InPath(-20.0);
  w.Apply(e.Step(p));
  const int hold_frames = static_cast<int>(std::floor(opt.avoid_hold_s / kDt + 1e-9));
  for (int i = 1; i < hold_frames + 5; ++i) w.Apply(e.Step(w.Perceive()));
  EXPECT_EQ(e.ObstacleOverrides(), hold_frames + 1);
}

TEST(ExplorerObstacleOverride, BlockedStopsThenTurnsToProbe) {
  EndlessCorridor w;
  ExplorerOptions opt;
  opt.avoid_blocked_frames = 2;
  opt.avoid_confirm_advices = 1;
  Explorer e(opt);
  StartFollowing(w, e);
  const int ends_before = e.EndsDetected();
  Percept p = w.Perceive();
  p.obstacles = InPath(0.0, true);
  Command c = e.Step(p);
  EXPECT_EQ(c.v_mps, 0.0);  // stop at once; wait for a second blocked advice
  EXPECT_EQ(c.omega_rps, 0.0);
  EXPECT_EQ(e.State(), ExploreState::kFollow);
  w.Apply(c);
  c = e.Step(w.Perceive());  // held: still stopped
  EXPECT_EQ(c.v_mps, 0.0);
  w.Apply(c);
  p = w.Perceive();
  p.obstacles = InPath(0.0, true);
  c = e.Step(p);
  EXPECT_EQ(c.v_mps, 0.0);
  EXPECT_EQ(e.ObstacleStops(), 1);
  EXPECT_EQ(e.Events().back().kind, ExploreEvent::Kind::kStall);
  // Then it stops and turns: probing the sides in place, never driving forward.
  bool rotated = false;
  for (int i = 0; i < 60; ++i) {
    w.Apply(c);
    c = e.Step(w.Perceive());
    EXPECT_LE(c.v_mps, 0.0) << i;
    rotated = rotated || std::abs(c.omega_rps) > 0.1;
  }
  EXPECT_TRUE(rotated);
  EXPECT_EQ(e.EndsDetected(), ends_before + 1);
  EXPECT_NE(e.State(), ExploreState::kFollow);
}

TEST(ExplorerObstacleOverride, ActsOnlyOnConfirmedObstacles) {
  EndlessCorridor w;
  ExplorerOptions opt;  // avoid_confirm_advices = 2
  ASSERT_EQ(opt.avoid_confirm_advices, 2);
  Explorer e(opt);
  StartFollowing(w, e);
  // One in-path advice between clear ones: ignored.
  Percept p = w.Perceive();
  p.obstacles = InPath(20.0);
  Command c = e.Step(p);
  EXPECT_NEAR(c.omega_rps, 0.0, 1e-9);
  EXPECT_NEAR(c.v_mps, opt.cruise_speed_mps, 1e-9);
  w.Apply(c);
  p = w.Perceive();
  p.obstacles = ObstacleAdvice{};
  w.Apply(e.Step(p));
  p = w.Perceive();
  p.obstacles = InPath(20.0);
  w.Apply(e.Step(p));
  EXPECT_EQ(e.ObstacleOverrides(), 0);
  // The second consecutive one acts.
  p = w.Perceive();
  p.obstacles = InPath(20.0);
  c = e.Step(p);
  EXPECT_EQ(e.ObstacleOverrides(), 1);
  EXPECT_GT(c.omega_rps, 0.0);
  EXPECT_NEAR(c.v_mps, opt.cruise_speed_mps * opt.avoid_speed_fraction, 1e-12);
}

TEST(ExplorerObstacleOverride, OptionsValidated) {
  ExplorerOptions opt;
  opt.avoid_hold_s = 0.0;
  EXPECT_FALSE(opt.Validate().empty());
  opt = {};
  opt.avoid_blocked_frames = 0;
  EXPECT_FALSE(opt.Validate().empty());
  opt = {};
  opt.avoid_confirm_advices = 0;
  EXPECT_FALSE(opt.Validate().empty());
}

}  // namespace
}  // namespace squint::explore
