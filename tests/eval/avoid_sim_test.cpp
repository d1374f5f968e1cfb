// Tests of the steering-only simulator runs: the rule after unclassified pairs (stall, blind
// drive after a turn) and the obstacle-course run that used to graze a box.
#include "squint/eval/avoid_sim.hpp"

#include <gtest/gtest.h>

#include "squint/sim/world.hpp"

namespace squint::eval {
namespace {

using obstacles::PairStatus;

TEST(AvoidSimTest, NoMotionWhileDrivenForwardIsAStall) {
  bool stalled = false;
  EXPECT_EQ(ChooseBlindMove(PairStatus::kNoMotion, true, true, &stalled), BlindMove::kTurn);
  EXPECT_TRUE(stalled) << "commanded forward, no wheel progress";
  EXPECT_EQ(ChooseBlindMove(PairStatus::kNoMotion, false, true, &stalled), BlindMove::kDriveOn);
  EXPECT_FALSE(stalled) << "it was turning or standing: no stall";
  EXPECT_EQ(ChooseBlindMove(PairStatus::kNoMotion, false, false, &stalled), BlindMove::kTurn);
  EXPECT_FALSE(stalled);
}

TEST(AvoidSimTest, AfterATurnDrivesOnOnlyAlongAClearPath) {
  bool stalled = true;
  EXPECT_EQ(ChooseBlindMove(PairStatus::kPureRotation, false, true, &stalled), BlindMove::kDriveOn);
  EXPECT_FALSE(stalled);
  EXPECT_EQ(ChooseBlindMove(PairStatus::kPureRotation, false, false, &stalled), BlindMove::kTurn);
  // A pure rotation is motion: never a stall, even when driven forward.
  EXPECT_EQ(ChooseBlindMove(PairStatus::kPureRotation, true, true, &stalled), BlindMove::kDriveOn);
  EXPECT_FALSE(stalled);
}

TEST(AvoidSimTest, OtherFailuresTurn) {
  for (PairStatus s : {PairStatus::kTooFewFeatures, PairStatus::kBadImage, PairStatus::kMissingOdometry}) {
    bool stalled = true;
    EXPECT_EQ(ChooseBlindMove(s, true, true, &stalled), BlindMove::kTurn) << obstacles::PairStatusName(s);
    EXPECT_FALSE(stalled);
  }
  EXPECT_EQ(ChooseBlindMove(PairStatus::kNoMotion, true, true, nullptr), BlindMove::kTurn);
}

// Seed 7 of `squint eval avoid-sim` grazed obstacles[0] (a box with a plain face) at 75.6 s and
// then pushed against it for the rest of the run.
TEST(AvoidSimTest, ObstacleCourseSeed7IsCollisionFree) {
  const sim::World world = sim::LoadWorld("obstacle-course");
  const AvoidSimRun run = RunAvoidSim(world, {}, {}, 7);
  EXPECT_EQ(run.collisions, 0) << run.first_hit << " at " << run.first_collision_s << " s";
  EXPECT_EQ(run.stalls, 0);
  EXPECT_GT(run.distance_m, 3.0);
}

}  // namespace
}  // namespace squint::eval
