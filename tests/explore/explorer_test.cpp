// The exploration state machine on scripted estimates: a toy corridor whose "perception" is
// computed analytically from the pose (heading, centring cue, distance to the end, entropy by
// the direction faced), closed through ideal unicycle motion. Checks end → stop → probe → turn,
// dead ends, starting facing a wall, centring, and heading held through gated frames.
#include "squint/explore/explorer.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "squint/core/angles.hpp"

namespace squint::explore {
namespace {

constexpr double kDt = 1.0 / 30.0;
// Glance entropies (nats) like the simulator's: about 3.3 looking down a corridor, under 2 facing
// a wall at a metre or so.
constexpr double kOpenEntropy = 3.3;
constexpr double kWallEntropy = 1.8;

// A corridor along +x from x = 0 to an end wall at x = 10; at the end, side corridors to the
// left (+y) and/or right (−y) as configured; behind the start, a wall.
struct ToyCorridor {
  bool left_open = true;
  bool right_open = false;
  int process_every = 3;        // rapid-perception gate: one frame in N fully processed
  double odom_drift_rad_per_m = 0.0;

  Pose2 pose;        // true pose
  Pose2 odom;        // odometry
  int frame = 0;

  Percept Perceive() const {
    Percept p;
    p.stamp_s = frame * kDt;
    p.odom_T_robot = odom;
    const int dir = static_cast<int>(std::lround(WrapPi(pose.yaw) / (kPi / 2))) & 3;
    const double axis = dir * kPi / 2;
    const double heading_deg = RadToDeg(WrapPi(pose.yaw - axis));
    const bool at_end = pose.x > 8.0;
    const bool wall_fills_view = pose.x > 9.0;  // the end wall fills the view within ~1 m
    bool open = false;
    double dist = 30.0;
    double lateral = 0.0;
    switch (dir) {
      case 0: open = !wall_fills_view; dist = 10.0 - pose.x; lateral = pose.y; break;
      case 1: open = at_end && left_open; lateral = 10.0 - pose.x - 1.0; break;
      case 2: open = pose.x > 5.0; dist = pose.x; lateral = -pose.y; break;  // the start end is near
      case 3: open = at_end && right_open; lateral = pose.x - 9.0; break;
    }
    p.glance_entropy_nats = (open ? kOpenEntropy : kWallEntropy) - 0.2 * std::abs(heading_deg) / 45.0;
    p.processed = frame % process_every == 0;
    if (p.processed) {
      p.heading_deg = heading_deg;
      // The symmetry axis moves about 40° per metre of lateral offset in the simulator.
      p.centre_heading_deg = heading_deg + 40.0 * lateral;
      p.dist_end_m = dist;
    }
    return p;
  }

  void Apply(const Command& c) {
    const double ds = c.v_mps * kDt;
    const double mid = pose.yaw + 0.5 * c.omega_rps * kDt;
    pose.x += ds * std::cos(mid);
    pose.y += ds * std::sin(mid);
    pose.yaw = WrapPi(pose.yaw + c.omega_rps * kDt);
    const double odom_mid = odom.yaw + 0.5 * c.omega_rps * kDt;
    odom.x += ds * std::cos(odom_mid);
    odom.y += ds * std::sin(odom_mid);
    odom.yaw = WrapPi(odom.yaw + c.omega_rps * kDt + odom_drift_rad_per_m * std::abs(ds));
    ++frame;
  }
};

struct ScriptedRun {
  std::vector<ExploreState> states;
  std::vector<Command> commands;
  double end_x = 0.0;
};

// Steps until `turns` turns were decided and the robot follows again, or the step budget ends.
ScriptedRun RunUntilTurns(ToyCorridor& world, Explorer& explorer, int turns, int max_steps = 30 * 120) {
  ScriptedRun run;
  for (int i = 0; i < max_steps; ++i) {
    const Command c = explorer.Step(world.Perceive());
    run.states.push_back(explorer.State());
    run.commands.push_back(c);
    if (explorer.EndsDetected() == 0) run.end_x = world.pose.x;
    world.Apply(c);
    if (explorer.Turns() >= turns && explorer.State() == ExploreState::kFollow) break;
  }
  return run;
}

std::vector<ExploreEvent::Kind> Kinds(const Explorer& e) {
  std::vector<ExploreEvent::Kind> k;
  for (const ExploreEvent& ev : e.Events()) k.push_back(ev.kind);
  return k;
}

TEST(Explorer, EndDetectedStopProbeTurnTowardOpenLeft) {
  ToyCorridor world;
  Explorer explorer;
  const ScriptedRun run = RunUntilTurns(world, explorer, 1);
  ASSERT_EQ(explorer.Turns(), 1);
  using K = ExploreEvent::Kind;
  EXPECT_EQ(Kinds(explorer), (std::vector<K>{K::kScanDone, K::kEndDetected, K::kTurn}));
  EXPECT_EQ(explorer.Events().back().turn_deg, 90);
  // Stopped short of the end wall (at 10 m) by about the stop distance.
  EXPECT_GT(run.end_x, 10.0 - 1.1 - 0.5);
  EXPECT_LT(run.end_x, 10.0 - 0.25 - 0.4);  // robot radius plus a margin before the wall
  // It never drove while probing or turning: decide by looking, standing still.
  for (std::size_t i = 0; i < run.states.size(); ++i) {
    if (run.states[i] == ExploreState::kProbe || run.states[i] == ExploreState::kTurn) {
      EXPECT_EQ(run.commands[i].v_mps, 0.0) << "step " << i;
    }
  }
  // It looked at both sides and now faces the open left corridor.
  const TopoNode& node = explorer.Map().Nodes().at(0);
  EXPECT_EQ(node.branch[1], Branch::kExplored);  // left: open, now being driven
  EXPECT_EQ(node.branch[3], Branch::kWall);
  EXPECT_EQ(node.branch[0], Branch::kWall);
  EXPECT_NEAR(RadToDeg(world.pose.yaw), 90.0, 3.0);
}

TEST(Explorer, TurnsRightWhenOnlyRightIsOpen) {
  ToyCorridor world;
  world.left_open = false;
  world.right_open = true;
  Explorer explorer;
  RunUntilTurns(world, explorer, 1);
  ASSERT_EQ(explorer.Turns(), 1);
  EXPECT_EQ(explorer.Events().back().turn_deg, -90);
  EXPECT_NEAR(RadToDeg(world.pose.yaw), -90.0, 3.0);
}

TEST(Explorer, DeadEndTurnsAround) {
  ToyCorridor world;
  world.left_open = false;
  world.right_open = false;
  Explorer explorer;
  RunUntilTurns(world, explorer, 1);
  ASSERT_EQ(explorer.Turns(), 1);
  EXPECT_EQ(explorer.Events().back().turn_deg, 180);
  EXPECT_NEAR(std::abs(RadToDeg(world.pose.yaw)), 180.0, 3.0);
}

TEST(Explorer, StartingFacingAWallFindsTheCorridor) {
  ToyCorridor world;
  world.pose = {2.0, 0.0, DegToRad(90.0)};  // facing the left wall
  world.odom = {};                          // odometry starts at the identity
  Explorer explorer;
  for (int i = 0; i < 30 * 20 && explorer.State() != ExploreState::kFollow; ++i) world.Apply(explorer.Step(world.Perceive()));
  ASSERT_EQ(explorer.State(), ExploreState::kFollow);
  // The scan's entropy maximum is down the corridor (+x), within one scan bin.
  EXPECT_NEAR(RadToDeg(world.pose.yaw), 0.0, 10.0 + 1.0);
  // Following then aligns it with the axis.
  for (int i = 0; i < 30 * 6; ++i) world.Apply(explorer.Step(world.Perceive()));
  EXPECT_NEAR(RadToDeg(world.pose.yaw), 0.0, 2.0);
  EXPECT_GT(world.pose.x, 4.0);
}

TEST(Explorer, CentresFromTheTranslationSensitiveCue) {
  ToyCorridor world;
  world.pose = {0.5, 0.6, 0.0};  // close to the left wall
  Explorer explorer;
  while (explorer.State() != ExploreState::kFollow) world.Apply(explorer.Step(world.Perceive()));
  for (int i = 0; i < 30 * 12 && world.pose.x < 7.5; ++i) world.Apply(explorer.Step(world.Perceive()));
  EXPECT_GT(world.pose.x, 7.0);
  EXPECT_LT(std::abs(world.pose.y), 0.15);
}

TEST(Explorer, HeadingHeldThroughGatedFramesDespiteOdometryDrift) {
  ToyCorridor world;
  world.process_every = 10;               // 90% of frames skipped by the gate
  world.odom_drift_rad_per_m = 0.02;      // 1.1° of yaw drift per metre
  Explorer explorer;
  while (explorer.State() != ExploreState::kFollow) world.Apply(explorer.Step(world.Perceive()));
  double worst_deg = 0.0;
  for (int i = 0; i < 30 * 20 && world.pose.x < 8.0; ++i) {
    world.Apply(explorer.Step(world.Perceive()));
    if (world.pose.x > 2.0) worst_deg = std::max(worst_deg, std::abs(RadToDeg(world.pose.yaw)));
  }
  EXPECT_GT(world.pose.x, 7.5);
  EXPECT_LT(worst_deg, 3.0);
}

TEST(Explorer, GateResetOncePerCorridor) {
  ToyCorridor world;
  Explorer explorer;
  EXPECT_TRUE(explorer.TakeGateReset());
  EXPECT_FALSE(explorer.TakeGateReset());
  RunUntilTurns(world, explorer, 1);
  EXPECT_TRUE(explorer.TakeGateReset());  // a new corridor started
}

TEST(Explorer, OptionsValidateNamesTheField) {
  ExplorerOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.end_stop_dist_m = -1.0;
  EXPECT_NE(o.Validate().find("end_stop_dist_m"), std::string::npos);
  o = {};
  o.map.merge_radius_m = 0.0;
  EXPECT_NE(o.Validate().find("merge_radius_m"), std::string::npos);
}

}  // namespace
}  // namespace squint::explore
