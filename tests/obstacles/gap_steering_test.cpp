// Tests of free-gap steering on hand-made polar occupancy.
#include "squint/obstacles/gap_steering.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"

namespace squint::obstacles {
namespace {

// 36 sectors of 5°, all in view and free, ROI 1.5 m; then `occupied` at `range`.
PolarMap Map(const std::vector<int>& occupied, double range_m = 1.0, const std::vector<int>& unseen = {}) {
  PolarMap m;
  m.roi_radius_m = 1.5;
  m.sector_deg = 5.0;
  m.sectors.resize(36);
  for (int i = 0; i < 36; ++i) {
    PolarSector& s = m.sectors[i];
    s.start_deg = -90.0 + 5.0 * i;
    s.end_deg = s.start_deg + 5.0;
    s.centre_deg = s.start_deg + 2.5;
    s.in_view = true;
    s.state = SectorState::kFree;
  }
  for (int i : occupied) {
    m.sectors[i].state = SectorState::kOccupied;
    m.sectors[i].contacts = 1;
    m.sectors[i].range_m = range_m;
  }
  for (int i : unseen) m.sectors[i].state = SectorState::kUnseen;
  return m;
}

std::vector<Gap> Gaps(const PolarMap& m, GapOptions o = {}) {
  std::vector<Gap> g;
  FindGaps(m, o, &g);
  return g;
}

TEST(GapSteeringTest, SteersToTheCentreOfTheWidestGap) {
  // Unseen outside [-30, 30]; occupied sectors 14 ([-20,-15]) and 20 ([10,15]) at 1.5 m. Gaps:
  // [-30,-20] (10°), [-15,10] (25°), [15,30] (15°). The widest is [-15, 10]: centre -2.5°.
  std::vector<int> unseen;
  for (int i = 0; i < 12; ++i) unseen.push_back(i);
  for (int i = 24; i < 36; ++i) unseen.push_back(i);
  const PolarMap m = Map({14, 20}, 1.5, unseen);
  const auto gaps = Gaps(m);
  ASSERT_EQ(gaps.size(), 3u);
  EXPECT_DOUBLE_EQ(gaps[0].start_deg, -30.0);
  EXPECT_DOUBLE_EQ(gaps[0].end_deg, -20.0);
  EXPECT_DOUBLE_EQ(gaps[1].start_deg, -15.0);
  EXPECT_DOUBLE_EQ(gaps[1].end_deg, 10.0);
  // Gap 1 lies between contacts at 1.5 m, 25° apart: the chord 2 r sin(12.5°) = 0.65 m.
  EXPECT_NEAR(gaps[1].width_m, 2.0 * 1.5 * std::sin(DegToRad(12.5)), 1e-12);
  EXPECT_TRUE(gaps[1].passable);
  // Gap 0's centre ray (-25°) passes 5° from the occupied sector's edge at -20°; the unseen
  // sectors on its other side do not narrow it.
  EXPECT_NEAR(gaps[0].width_m, 2.0 * 1.5 * std::sin(DegToRad(5.0)), 1e-12);
  EXPECT_FALSE(gaps[0].passable);
  const SteeringDecision d = ChooseSteering(gaps);
  ASSERT_FALSE(d.stop);
  EXPECT_DOUBLE_EQ(*d.steer_deg, -2.5);
  EXPECT_EQ(*d.gap, 1);
}

TEST(GapSteeringTest, NarrowGapsAreExcluded) {
  // Occupied everywhere except sectors 17..18 ([-5, 5]) with walls at 1.0 m: the gap is
  // 2 sin(5°) = 0.17 m wide, narrower than 2 (0.25 + 0.05) = 0.6 m.
  std::vector<int> occ;
  for (int i = 0; i < 36; ++i)
    if (i != 17 && i != 18) occ.push_back(i);
  const auto gaps = Gaps(Map(occ));
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_FALSE(gaps[0].passable);
  const SteeringDecision d = ChooseSteering(gaps);
  EXPECT_TRUE(d.stop);
  EXPECT_FALSE(d.steer_deg.has_value());
  // A smaller robot passes the same gap.
  GapOptions small;
  small.robot_radius_m = 0.05;
  small.margin_m = 0.02;
  EXPECT_FALSE(ChooseSteering(Gaps(Map(occ), small)).stop);
}

TEST(GapSteeringTest, NarrowWidestGapLosesToAPassableOne) {
  // Occupied sectors 5 ([-65,-60]) at 0.3 m, 20 ([10,15]) at 0.5 m, 26 ([40,45]) at 1.4 m.
  // Gap [6..19] ([-60,10]) is the widest by angle (70°) but its centre ray passes 35° from the
  // contact at 0.3 m: 2 * 0.3 * sin(35°) = 0.34 m < 0.6 m. Gap [27..35] ([45,90], 45°) clears
  // 1.4 m * sin(22.5°) and 0.5 m * sin(52.5°) on each side: the widest passable one, centre 67.5°.
  PolarMap m = Map({5, 20, 26}, 0.3);
  m.sectors[20].range_m = 0.5;
  m.sectors[26].range_m = 1.4;
  const auto gaps = Gaps(m);
  ASSERT_EQ(gaps.size(), 4u);
  EXPECT_EQ(gaps[1].first, 6);
  EXPECT_NEAR(gaps[1].width_m, 2.0 * 0.3 * std::sin(DegToRad(35.0)), 1e-12);
  EXPECT_FALSE(gaps[1].passable);
  const SteeringDecision d = ChooseSteering(gaps);
  ASSERT_FALSE(d.stop);
  EXPECT_EQ(*d.gap, 3);
  EXPECT_DOUBLE_EQ(*d.steer_deg, 67.5);
}

TEST(GapSteeringTest, StopsWhenEverythingIsBlocked) {
  std::vector<int> all;
  for (int i = 0; i < 36; ++i) all.push_back(i);
  const auto gaps = Gaps(Map(all));
  EXPECT_TRUE(gaps.empty());
  const SteeringDecision d = ChooseSteering(gaps);
  EXPECT_TRUE(d.stop);
  EXPECT_FALSE(d.steer_deg.has_value());
}

TEST(GapSteeringTest, StopsWhenNothingIsSeen) {
  std::vector<int> all;
  for (int i = 0; i < 36; ++i) all.push_back(i);
  EXPECT_TRUE(ChooseSteering(Gaps(Map({}, 1.0, all))).stop);
}

TEST(GapSteeringTest, EqualGapsGoToTheOneNearerStraightAheadThenTheRightmost) {
  // Unseen outside [-40, 40]; occupied 16 ([-10,-5]) and 19 ([5,10]) at 1.5 m: gaps [-40,-10]
  // (30°), [-5,5] (10°, too narrow), [10,40] (30°). The two 30° gaps tie with equal |centre|.
  std::vector<int> unseen;
  for (int i = 0; i < 10; ++i) unseen.push_back(i);
  for (int i = 26; i < 36; ++i) unseen.push_back(i);
  const auto gaps = Gaps(Map({16, 19}, 1.5, unseen));
  ASSERT_EQ(gaps.size(), 3u);
  EXPECT_FALSE(gaps[1].passable);
  const SteeringDecision d = ChooseSteering(gaps);
  ASSERT_FALSE(d.stop);
  EXPECT_DOUBLE_EQ(*d.steer_deg, -25.0);
  // Make the left gap one sector wider: it wins.
  std::vector<int> unseen2(unseen.begin(), unseen.end());
  unseen2.erase(std::find(unseen2.begin(), unseen2.end(), 26));
  EXPECT_DOUBLE_EQ(*ChooseSteering(Gaps(Map({16, 19}, 1.5, unseen2))).steer_deg, 27.5);
}

TEST(GapSteeringTest, StraightPathFreeIsTheFootprintSweptAlongTheHeading) {
  // A disc of radius 0.3 m moving 2 m along +x sweeps the points within 0.3 m of the segment
  // from (0, 0) to (2, 0).
  const auto clear = [](std::vector<Eigen::Vector2d> p) { return StraightPathFree(p, 2.0, 0.3); };
  EXPECT_TRUE(clear({}));
  EXPECT_FALSE(clear({{1.0, 0.29}})) << "beside the path, 0.29 m from its axis";
  EXPECT_TRUE(clear({{1.0, 0.31}, {1.0, -0.31}}));
  EXPECT_FALSE(clear({{2.2, 0.0}})) << "0.2 m beyond the end: within the disc there";
  EXPECT_TRUE(clear({{2.31, 0.0}}));
  // Beyond the end the swept region is round: (2.2, 0.2) is 0.283 m from (2, 0), (2.25, 0.2) 0.32 m.
  EXPECT_FALSE(clear({{2.2, 0.2}}));
  EXPECT_TRUE(clear({{2.25, 0.2}}));
  EXPECT_TRUE(clear({{-0.1, 0.0}, {-0.5, 0.1}})) << "behind the robot";
  EXPECT_FALSE(clear({{0.0, 0.1}})) << "beside the centre";
  EXPECT_FALSE(StraightPathFree(std::vector<Eigen::Vector2d>{{0.1, 0.2}}, 0.0, 0.3)) << "length 0: the disc itself";
}

}  // namespace
}  // namespace squint::obstacles
