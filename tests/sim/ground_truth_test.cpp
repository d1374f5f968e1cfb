// Ground truth for known poses at a dead end and in T, L and cross junctions.
#include <gtest/gtest.h>

#include "squint/core/angles.hpp"
#include "squint/sim/ground_truth.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

World Make(const std::string& corridors) {
  return ParseWorld("format: squint-world/1\ncorridor_defaults: {width_m: 2}\ncorridors:\n" + corridors, "gt.yaml");
}

constexpr double kTol = 1e-9;

void Expect(const World& w, Pose2 pose, double heading_deg, double lateral, double dist) {
  const GroundTruth gt = GroundTruthAt(w, pose);
  ASSERT_TRUE(gt.heading_deg && gt.lateral_m && gt.dist_end_m);
  EXPECT_NEAR(*gt.heading_deg, heading_deg, 1e-7);
  EXPECT_NEAR(*gt.lateral_m, lateral, kTol);
  EXPECT_NEAR(*gt.dist_end_m, dist, kTol);
}

TEST(GroundTruth, DeadEnd) {
  const World w = Make("  - {from: [0, 0], to: [20, 0]}\n");
  Expect(w, {5, 0.3, DegToRad(10)}, 10, 0.3, 16.0);  // end wall at x = 21
  Expect(w, {5, 0.3, DegToRad(-25)}, -25, 0.3, 16.0);
  // Facing back: the axis flips, left is now -y.
  Expect(w, {5, 0.3, DegToRad(175)}, -5, -0.3, 6.0);
}

TEST(GroundTruth, TJunction) {
  const World w = Make("  - {name: stem, from: [0, 0], to: [20, 0]}\n  - {name: bar, from: [20, -10], to: [20, 10]}\n");
  Expect(w, {5, -0.2, 0}, 0, -0.2, 16.0);                  // far wall of the bar at x = 21
  Expect(w, {20, -5, DegToRad(90)}, 0, 0, 16.0);           // along the bar, past the stem's opening
  Expect(w, {20.3, 4, DegToRad(-92)}, -2, 0.3, 15.0);      // along the bar the other way
  Expect(w, {12, 0, DegToRad(180)}, 0, 0, 13.0);           // back down the stem to its dead end
}

TEST(GroundTruth, LJunction) {
  const World w = Make("  - {name: a, from: [0, 0], to: [20, 0]}\n  - {name: b, from: [20, 0], to: [20, 10]}\n");
  Expect(w, {5, 0, 0}, 0, 0, 16.0);
  // In the corner square facing +y: the current corridor is b.
  Expect(w, {20.5, 0.5, DegToRad(88)}, -2, -0.5, 10.5);
  const auto f = CurrentCorridor(w, {20.5, 0.5, DegToRad(88)});
  ASSERT_TRUE(f);
  EXPECT_EQ(f->corridor, 1);
}

TEST(GroundTruth, CrossJunctionIsPassedThrough) {
  const World w = Make("  - {name: a, from: [0, 0], to: [20, 0]}\n  - {name: b, from: [10, -10], to: [10, 10]}\n");
  Expect(w, {5, 0.4, DegToRad(3)}, 3, 0.4, 16.0);
  Expect(w, {10, -8, DegToRad(90)}, 0, 0, 19.0);
}

TEST(GroundTruth, OutsideTheFloorIsUnknown) {
  const World w = Make("  - {from: [0, 0], to: [20, 0]}\n");
  const GroundTruth gt = GroundTruthAt(w, {5, 3, 0});
  EXPECT_FALSE(gt.heading_deg);
  EXPECT_FALSE(gt.dist_end_m);
}

}  // namespace
}  // namespace squint::sim
