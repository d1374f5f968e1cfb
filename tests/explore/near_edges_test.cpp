// Vertical edges ranged by the parallax of the robot's travel (explore/near_edges.hpp) on
// constructed horizon profiles: a wall's face of one grey ending at a corner, seen against a
// background of another, each column's grey the area-weighted mix of what its width covers.
#include "squint/explore/near_edges.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::explore {
namespace {

constexpr int kColumns = 64;
const double kHalf = DegToRad(27.5);

std::vector<double> Bearings() {
  std::vector<double> b(kColumns);
  for (int i = 0; i < kColumns; ++i) b[static_cast<std::size_t>(i)] = kHalf - 2.0 * kHalf * i / (kColumns - 1);
  return b;
}

// The profile seen from `robot` of a face (grey `face`) covering the bearings left of the
// corner at `corner` (world frame), the background (`back`) elsewhere.
std::vector<float> FaceProfile(const Pose2& robot, const Eigen::Vector2d& corner, float face = 130.0f, float back = 108.0f) {
  const std::vector<double> b = Bearings();
  const double step = b[0] - b[1];
  const Eigen::Vector2d q = corner - robot.Translation();
  const double edge = WrapPi(std::atan2(q.y(), q.x()) - robot.yaw);
  std::vector<float> p(kColumns);
  for (int i = 0; i < kColumns; ++i) {
    const double hi = b[static_cast<std::size_t>(i)] + 0.5 * step;  // the column's left side
    const double face_part = std::clamp((hi - edge) / step, 0.0, 1.0);  // its share left of the edge
    p[static_cast<std::size_t>(i)] = static_cast<float>(face_part * face + (1.0 - face_part) * back);
  }
  return p;
}

TEST(NearEdges, ACornerInsideTheBlindRangeIsRangedByTheTravel) {
  // The corner 0.35 m from the start, 11 degrees to the left of the way the robot drives.
  const Pose2 p0{0.0, 0.0, 0.0};
  const Eigen::Vector2d corner(0.35 * std::cos(DegToRad(11.0)), 0.35 * std::sin(DegToRad(11.0)));
  NearEdgeRanger ranger;
  EXPECT_TRUE(ranger.Process(FaceProfile(p0, corner), Bearings(), p0).empty());  // one frame: nothing to range
  const Pose2 p0b{0.0, 0.0, DegToRad(-2.0)};  // turned a little in place (aligning)
  EXPECT_TRUE(ranger.Process(FaceProfile(p0b, corner), Bearings(), p0b).empty());
  // 0.06 m on (with a small turn, which the odometry knows): the edge has moved about 2 degrees,
  // and both kept frames range it alike.
  const Pose2 p1{0.06, 0.0, DegToRad(1.0)};
  const std::vector<NearEdge>& edges = ranger.Process(FaceProfile(p1, corner), Bearings(), p1);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_NEAR(edges[0].range_m, (corner - p1.Translation()).norm(), 0.03);
  EXPECT_NEAR((edges[0].point - corner).norm(), 0.0, 0.03);
  const Eigen::Vector2d q = corner - p1.Translation();
  const double bearing = std::atan2(q.y(), q.x()) - p1.yaw;
  EXPECT_NEAR(edges[0].bearing_rad, bearing, DegToRad(0.2));
  EXPECT_NEAR(edges[0].column, (kHalf - bearing) / (2.0 * kHalf) * (kColumns - 1), 0.25);
}

TEST(NearEdges, AFarEdgeOrATurnInPlaceGivesNothing) {
  const Pose2 p0{0.0, 0.0, 0.0};
  const Eigen::Vector2d far(3.0 * std::cos(DegToRad(11.0)), 3.0 * std::sin(DegToRad(11.0)));
  NearEdgeRanger ranger;
  ranger.Process(FaceProfile(p0, far), Bearings(), p0);
  ranger.Process(FaceProfile({0.0, 0.0, 0.02}, far), Bearings(), {0.0, 0.0, 0.02});
  const Pose2 p1{0.06, 0.0, 0.0};
  EXPECT_TRUE(ranger.Process(FaceProfile(p1, far), Bearings(), p1).empty());
  // Turning in place about the camera's foot: every edge moves by the turn alone.
  const Eigen::Vector2d near(0.35 * std::cos(DegToRad(11.0)), 0.35 * std::sin(DegToRad(11.0)));
  NearEdgeRanger turning;
  for (int k = 0; k <= 10; ++k) {
    const Pose2 p{0.0, 0.0, DegToRad(1.5 * k)};
    EXPECT_TRUE(turning.Process(FaceProfile(p, near), Bearings(), p).empty()) << k;
  }
}

// The same corner, but the frame kept is too far back (beyond max_baseline_m) or the robot
// turned too far since (max_turn_rad): nothing. A reset forgets the kept frames.
TEST(NearEdges, OnlyFramesCloseEnoughAndFacingAlikeArePaired) {
  const Eigen::Vector2d corner(0.45, 0.12);
  const Pose2 p0{0.0, 0.0, 0.0}, p0b{0.0, 0.0, DegToRad(-2.0)};
  {
    NearEdgeRanger ranger;
    ranger.Process(FaceProfile(p0, corner), Bearings(), p0);
    ranger.Process(FaceProfile(p0b, corner), Bearings(), p0b);
    const Pose2 p1{0.4, 0.0, 0.0};  // 0.4 m on
    EXPECT_TRUE(ranger.Process(FaceProfile(p1, corner), Bearings(), p1).empty());
  }
  {
    NearEdgeRanger ranger;
    ranger.Process(FaceProfile(p0, corner), Bearings(), p0);
    ranger.Process(FaceProfile(p0b, corner), Bearings(), p0b);
    const Pose2 p1{0.06, 0.0, DegToRad(30.0)};  // turned 30 degrees on the way
    EXPECT_TRUE(ranger.Process(FaceProfile(p1, corner), Bearings(), p1).empty());
  }
  {
    NearEdgeRanger ranger;
    ranger.Process(FaceProfile(p0, corner), Bearings(), p0);
    ranger.Process(FaceProfile(p0b, corner), Bearings(), p0b);
    ranger.Reset();
    const Pose2 p1{0.06, 0.0, 0.0}, p1b{0.06, 0.0, DegToRad(-2.0)};
    EXPECT_TRUE(ranger.Process(FaceProfile(p1, corner), Bearings(), p1).empty());
    EXPECT_TRUE(ranger.Process(FaceProfile(p1b, corner), Bearings(), p1b).empty());
    const Pose2 p2{0.12, 0.0, 0.0};
    EXPECT_EQ(ranger.Process(FaceProfile(p2, corner), Bearings(), p2).size(), 1u);
  }
}

// The two kept frames must range an edge alike: a second frame whose edge stands 3 degrees off
// where the corner would put it (something that moved, or an edge mismatched) gives nothing.
TEST(NearEdges, TheTwoPairsMustAgree) {
  const Eigen::Vector2d corner(0.45, 0.12);
  const Pose2 p0{0.0, 0.0, 0.0}, p0b{0.0, 0.0, DegToRad(-2.0)}, p1{0.06, 0.0, 0.0};
  const double off = DegToRad(3.0);
  const Eigen::Vector2d moved(corner.norm() * std::cos(std::atan2(corner.y(), corner.x()) + off),
                              corner.norm() * std::sin(std::atan2(corner.y(), corner.x()) + off));
  for (const bool agree : {true, false}) {
    NearEdgeRanger ranger;
    ranger.Process(FaceProfile(p0, corner), Bearings(), p0);
    ranger.Process(FaceProfile(p0b, agree ? corner : moved), Bearings(), p0b);
    EXPECT_EQ(ranger.Process(FaceProfile(p1, corner), Bearings(), p1).size(), agree ? 1u : 0u) << agree;
  }
}

// Two like edges within the match window: which one moved where cannot be told, so nothing.
// Two faces of the same grey whose corners lie 4 degrees apart, 0.35 m away, seen over a window
// of 5.7 degrees: each edge of the second frame has two candidates. Either face alone is ranged.
TEST(NearEdges, AnAmbiguousMatchGivesNothing) {
  const Pose2 p0{0.0, 0.0, 0.0}, p1{0.06, 0.0, 0.0};
  const Eigen::Vector2d a(0.35 * std::cos(DegToRad(10.0)), 0.35 * std::sin(DegToRad(10.0)));
  const Eigen::Vector2d b(0.35 * std::cos(DegToRad(14.0)), 0.35 * std::sin(DegToRad(14.0)));
  auto both = [&](const Pose2& robot) {
    const std::vector<float> fa = FaceProfile(robot, a), fb = FaceProfile(robot, b);
    std::vector<float> p(kColumns);
    for (int i = 0; i < kColumns; ++i) p[static_cast<std::size_t>(i)] = 0.5f * (fa[static_cast<std::size_t>(i)] + fb[static_cast<std::size_t>(i)]);
    return p;
  };
  NearEdgeOptions o;
  o.match_window_rad = 0.1;
  const Pose2 p0b{0.0, 0.0, DegToRad(-2.0)};
  NearEdgeRanger two(o);
  two.Process(both(p0), Bearings(), p0);
  two.Process(both(p0b), Bearings(), p0b);
  EXPECT_TRUE(two.Process(both(p1), Bearings(), p1).empty());
  for (const Eigen::Vector2d& c : {a, b}) {
    NearEdgeRanger one(o);
    one.Process(FaceProfile(p0, c), Bearings(), p0);
    one.Process(FaceProfile(p0b, c), Bearings(), p0b);
    const std::vector<NearEdge>& e = one.Process(FaceProfile(p1, c), Bearings(), p1);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_NEAR(e[0].range_m, (c - p1.Translation()).norm(), 0.03);
  }
}

TEST(NearEdges, BadOptionsAndInputsAreErrors) {
  NearEdgeOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.min_baseline_m = 0.5;  // above max_baseline_m
  EXPECT_FALSE(o.Validate().empty());
  EXPECT_THROW(NearEdgeRanger{o}, Error);
  NearEdgeRanger ranger;
  std::vector<float> p(10, 100.0f);
  std::vector<double> b(9, 0.0);
  EXPECT_THROW(ranger.Process(p, b, Pose2{}), std::logic_error);
}

}  // namespace
}  // namespace squint::explore
