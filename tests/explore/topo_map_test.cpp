// The topological map on a scripted walk: nodes merge by position, edges link departures to
// arrivals, and the next branch prefers unexplored corridors, then the nearest node with one.
#include "squint/explore/topo_map.hpp"

#include <gtest/gtest.h>

#include "squint/core/angles.hpp"

namespace squint::explore {
namespace {

TEST(TopoMap, DirectionsOfYaw) {
  EXPECT_EQ(DirectionOfYaw(0.0), 0);
  EXPECT_EQ(DirectionOfYaw(DegToRad(80.0)), 1);
  EXPECT_EQ(DirectionOfYaw(DegToRad(-100.0)), 3);
  EXPECT_EQ(DirectionOfYaw(DegToRad(179.0)), 2);
  EXPECT_EQ(DirectionOfYaw(DegToRad(-179.0)), 2);
  EXPECT_NEAR(YawOfDirection(3), -kPi / 2, 1e-12);
  EXPECT_EQ(Opposite(1), 3);
}

// A 10 m square loop A(0,0) B(10,0) C(10,10) D(0,10) with a dead-end stem from B going to
// E(10,-6). The robot starts at A heading east.
TEST(TopoMap, ScriptedWalkAroundLoopWithStem) {
  TopoMap map;
  // Stop at B (a T: north open, south open, east wall).
  const int b = map.Arrive({10.0, 0.2}, 0);
  EXPECT_EQ(b, 0);
  map.SetBranch(b, 0, Branch::kWall);
  map.SetBranch(b, 1, Branch::kOpen);
  map.SetBranch(b, 3, Branch::kOpen);
  EXPECT_EQ(map.Nodes()[b].branch[2], Branch::kExplored);  // the way it came
  // Left first among unexplored branches.
  EXPECT_EQ(map.ChooseBranch(b, 0), 1);
  map.Depart(b, 1);
  // C: an L corner (west open).
  const int c = map.Arrive({10.1, 10.0}, 1);
  EXPECT_EQ(c, 1);
  map.SetBranch(c, 1, Branch::kWall);
  map.SetBranch(c, 2, Branch::kOpen);
  map.SetBranch(c, 0, Branch::kWall);
  ASSERT_EQ(map.Nodes()[b].neighbour[1], c);
  EXPECT_EQ(map.Nodes()[c].neighbour[3], b);
  EXPECT_NEAR(map.Nodes()[b].length_m[1], 9.8, 0.05);
  // C's only unexplored branch is west; B's south is still open.
  EXPECT_EQ(map.ChooseBranch(c, 1), 2);
  map.Depart(c, 2);
  const int d = map.Arrive({0.0, 10.0}, 2);
  map.SetBranch(d, 2, Branch::kWall);
  map.SetBranch(d, 1, Branch::kWall);
  map.SetBranch(d, 3, Branch::kOpen);
  map.Depart(d, 3);
  // Back at the start corner A (new node: the start itself was not a stop).
  const int a = map.Arrive({0.3, -0.2}, 3);
  map.SetBranch(a, 3, Branch::kWall);
  map.SetBranch(a, 2, Branch::kWall);
  map.SetBranch(a, 0, Branch::kOpen);
  EXPECT_EQ(map.Nodes().size(), 4u);
  EXPECT_EQ(map.ChooseBranch(a, 3), 0);  // east, never driven from here
  map.Depart(a, 0);
  // Arriving at B again merges with node b (within the merge radius) and links A–B.
  const int b2 = map.Arrive({9.0, -0.5}, 0);
  EXPECT_EQ(b2, b);
  EXPECT_EQ(map.Nodes().size(), 4u);
  EXPECT_EQ(map.NumEdges(), 4);
  // The south stem is the last unexplored branch: right turn.
  EXPECT_TRUE(map.HasUnexplored());
  EXPECT_EQ(map.ChooseBranch(b, 0), 3);
  map.Depart(b, 3);
  const int e = map.Arrive({10.0, -6.0}, 3);
  map.SetBranch(e, 3, Branch::kWall);
  map.SetBranch(e, 0, Branch::kWall);
  map.SetBranch(e, 2, Branch::kWall);
  EXPECT_FALSE(map.HasUnexplored());
  // Dead end, everything explored: the way back is the only passable branch.
  EXPECT_EQ(map.ChooseBranch(e, 3), 1);
}

TEST(TopoMap, ShortestPathToNearestUnexploredNode) {
  TopoMap map;
  // A chain X(0,0) -> Y(10,0) -> Z(20,0); X has an open north branch left behind.
  const int x = map.Arrive({0.0, 0.0}, 2);
  map.SetBranch(x, 1, Branch::kOpen);
  map.SetBranch(x, 2, Branch::kWall);
  map.SetBranch(x, 3, Branch::kWall);
  map.Depart(x, 0);
  const int y = map.Arrive({10.0, 0.0}, 0);
  map.SetBranch(y, 1, Branch::kWall);
  map.SetBranch(y, 3, Branch::kWall);
  map.Depart(y, 0);
  const int z = map.Arrive({20.0, 0.0}, 0);
  map.SetBranch(z, 0, Branch::kWall);
  map.SetBranch(z, 1, Branch::kWall);
  map.SetBranch(z, 3, Branch::kWall);
  // Nothing open at Z: head back west toward X's open branch.
  EXPECT_EQ(map.ChooseBranch(z, 0), 2);
  EXPECT_EQ(map.ChooseBranch(y, 0), 2);
}

TEST(TopoMap, ExploredBranchStaysExplored) {
  TopoMap map;
  const int n = map.Arrive({0.0, 0.0}, 0);
  map.SetBranch(n, 2, Branch::kWall);  // a later mis-look cannot close the way it came
  EXPECT_EQ(map.Nodes()[n].branch[2], Branch::kExplored);
}

// A robot that starts in a junction and stops there has not come along the branch behind it;
// one that departed from a node has, however short the way.
TEST(TopoMap, BranchBehindIsExploredOnlyWhenTheRobotCameAlongIt) {
  TopoMap map;
  const int n = map.Arrive({0.0, 0.0}, 2, /*came_along=*/false);
  EXPECT_EQ(map.Nodes()[n].branch[0], Branch::kUnknown);
  EXPECT_EQ(map.Nodes()[n].branch[2], Branch::kUnknown);
  map.SetBranch(n, 0, Branch::kWall);
  map.Depart(n, 1);
  const int m = map.Arrive({0.0, 5.0}, 1, /*came_along=*/false);
  EXPECT_NE(m, n);
  EXPECT_EQ(map.Nodes()[m].branch[3], Branch::kExplored);
  EXPECT_EQ(map.Nodes()[m].neighbour[3], n);
  EXPECT_EQ(map.Nodes()[n].branch[0], Branch::kWall);  // what was known stays
}

TEST(TopoMap, PatrolPrefersLeastRecentlyTaken) {
  TopoMap map;
  const int n = map.Arrive({0.0, 0.0}, 0);
  map.SetBranch(n, 0, Branch::kWall);
  map.SetBranch(n, 1, Branch::kExplored);
  map.SetBranch(n, 3, Branch::kExplored);
  map.SetBranch(n, 2, Branch::kExplored);
  map.Depart(n, 1);
  map.Arrive({0.0, 0.0}, 3);  // came back from the north
  map.Depart(n, 3);
  map.Arrive({0.0, 0.0}, 1);  // came back from the south
  // West (never departed), north (departed first), south: west is least recently taken.
  EXPECT_EQ(map.ChooseBranch(n, 1), 2);
}

// A corridor east from A(0,0) to a dead end B(20,0), with a side branch to the south met at
// J(10,0) from the bar of the T: the pass is a node of its own, splitting the edge A–B, and its
// unexplored branch is chosen first, and later reached back along known edges.
TEST(TopoMap, SideBranchPassedMidCorridorIsANodeAndIsChosen) {
  TopoMap map;
  const int a = map.Arrive({0.0, 0.0}, 2);  // the start: a stop facing west, then turned round
  map.SetBranch(a, 1, Branch::kWall);
  map.SetBranch(a, 3, Branch::kWall);
  map.Depart(a, 0);
  EXPECT_EQ(map.NodeNear({9.0, 0.5}), -1);
  // Passing J: the right (south) side is open, straight on continues.
  const int j = map.Arrive({10.0, 0.1}, 0);
  map.SetBranch(j, 3, Branch::kOpen);
  map.SetBranch(j, 1, Branch::kWall);
  map.SetBranch(j, 0, Branch::kOpen);
  EXPECT_EQ(map.NodeNear({9.0, 0.5}), j);
  EXPECT_EQ(map.Nodes()[a].neighbour[0], j);
  EXPECT_NEAR(map.Nodes()[a].length_m[0], 10.0, 0.01);
  // The side branch before straight on (both unexplored: right before straight).
  EXPECT_EQ(map.ChooseBranch(j, 0), 3);
  // Had it gone straight on instead: the dead end B routes back to J (west), the way to the
  // open south branch, along the known edge.
  map.Depart(j, 0);
  const int b = map.Arrive({20.0, 0.0}, 0);
  map.SetBranch(b, 0, Branch::kWall);
  map.SetBranch(b, 1, Branch::kWall);
  map.SetBranch(b, 3, Branch::kWall);
  EXPECT_EQ(map.Nodes()[j].neighbour[0], b);
  EXPECT_EQ(map.Nodes()[b].neighbour[2], j);
  EXPECT_EQ(map.NumEdges(), 2);
  EXPECT_EQ(map.ChooseBranch(b, 0), 2);
  map.Depart(b, 2);
  // Back at J heading west (a stop merged with J): the open south branch is now on the left.
  EXPECT_EQ(map.Arrive({10.3, -0.2}, 2), j);
  EXPECT_EQ(map.ChooseBranch(j, 2), 3);
}

// A T at B(10,0): the bar runs west to A(0,0) and east (a wall here), the stem south to a dead
// end C(10,-14). The robot came from A, drove the stem, came back up it to B and set off west,
// but stalled right after setting off (it stood inside the stem's mouth): the west branch is
// forced closed. For the rest of that visit it stays closed (the robot goes back down the stem:
// setting off west again from the same place would stall again). On the next arrival at B
// it is open again with reopen_blocked_driven, and the patrol takes it (least recently taken);
// without, B is a dead end for good and the robot shuttles between B and C.
TEST(TopoMap, DrivenCorridorBlockedAtSetOffIsReopenedOnTheNextArrival) {
  for (const bool reopen : {false, true}) {
    SCOPED_TRACE(reopen ? "reopen_blocked_driven" : "closed for good");
    TopoMapOptions options;
    options.reopen_blocked_driven = reopen;
    TopoMap map(options);
    const int a = map.Arrive({0.0, 0.0}, 0, /*came_along=*/false);
    map.SetBranch(a, 2, Branch::kWall);
    map.SetBranch(a, 1, Branch::kWall);
    map.SetBranch(a, 3, Branch::kWall);
    map.Depart(a, 0);
    const int b = map.Arrive({10.0, 0.0}, 0);  // along the bar, eastward
    map.SetBranch(b, 0, Branch::kWall);
    map.SetBranch(b, 1, Branch::kWall);
    map.Depart(b, 3);  // into the stem
    const int c = map.Arrive({10.0, -14.0}, 3);
    map.SetBranch(c, 0, Branch::kWall);
    map.SetBranch(c, 2, Branch::kWall);
    map.SetBranch(c, 3, Branch::kWall);
    map.Depart(c, 1);
    ASSERT_EQ(map.Arrive({10.0, -0.4}, 1), b);  // back up the stem, stopped in its mouth
    ASSERT_EQ(map.Nodes()[b].branch[2], Branch::kExplored);
    ASSERT_EQ(map.Nodes()[b].neighbour[2], a);
    EXPECT_EQ(map.ChooseBranch(b, 1), 2);  // the patrol: west, taken longest ago
    map.Depart(b, 2);
    map.CancelDeparture();                        // stalled right after setting off...
    map.SetBranch(b, 2, Branch::kWall, /*force=*/true);  // ...so the branch is closed
    EXPECT_EQ(map.Nodes()[b].branch[2], Branch::kWall);
    EXPECT_EQ(map.ChooseBranch(b, 2), 3);  // this visit: back down the stem either way
    map.Depart(b, 3);
    ASSERT_EQ(map.Arrive({10.0, -14.0}, 3), c);
    map.Depart(c, 1);
    ASSERT_EQ(map.Arrive({10.1, -0.3}, 1), b);
    if (reopen) {
      EXPECT_EQ(map.Nodes()[b].branch[2], Branch::kExplored);
      EXPECT_EQ(map.ChooseBranch(b, 1), 2);  // west again, from another stop
    } else {
      EXPECT_EQ(map.Nodes()[b].branch[2], Branch::kWall);
      EXPECT_EQ(map.ChooseBranch(b, 1), 3);  // the stem once more, for the rest of the run
    }
    // A branch closed by looking (not a driven corridor found blocked) stays closed either way.
    EXPECT_EQ(map.Nodes()[b].branch[0], Branch::kWall);
    EXPECT_EQ(map.Nodes()[b].branch[1], Branch::kWall);
  }
}

TEST(TopoMap, OptionsValidate) {
  TopoMapOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.merge_radius_m = 0.0;
  EXPECT_FALSE(o.Validate().empty());
}

}  // namespace
}  // namespace squint::explore
