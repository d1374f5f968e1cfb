// World loading: built-ins, derived walls, and every kind of bad world file failing with a
// message that names the file and the entry.
#include <gtest/gtest.h>

#include <string>

#include "squint/core/error.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

const char* kHeader = "format: squint-world/1\n";

std::string ErrorOf(const std::string& yaml) {
  try {
    ParseWorld(std::string(kHeader) + yaml, "bad.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(World, BuiltinsLoad) {
  const auto names = BuiltinWorldNames();
  ASSERT_GE(names.size(), 12u);
  for (const std::string& n : names) {
    const World w = LoadWorld(n);
    EXPECT_FALSE(w.walls.empty()) << n;
    EXPECT_FALSE(w.lights.empty()) << n;
  }
  int corridors = 0;
  for (const std::string& n : names) corridors += n.rfind("corridor-", 0) == 0;
  EXPECT_EQ(corridors, 10);
}

TEST(World, DefaultIsALoopOfAtLeast150Metres) {
  const World w = LoadWorld("default");
  EXPECT_GE(w.CorridorLength(), 150.0);
  // Going round the loop: the four corners are free, and the centre of the loop is not.
  for (const Eigen::Vector2d p : {Eigen::Vector2d(0, 0), Eigen::Vector2d(40, 0), Eigen::Vector2d(40, 25), Eigen::Vector2d(0, 25)})
    EXPECT_TRUE(w.IsFree(p));
  EXPECT_FALSE(w.IsFree({20, 6}));
}

TEST(World, SingleCorridorHasFourWalls) {
  const World w = ParseWorld(std::string(kHeader) + "corridors: [{from: [0, 0], to: [10, 0], width_m: 2}]\n", "one.yaml");
  ASSERT_EQ(w.walls.size(), 4u);
  const Box2 b = w.Bounds();
  EXPECT_DOUBLE_EQ(b.x0, -1.0);
  EXPECT_DOUBLE_EQ(b.x1, 11.0);
  EXPECT_DOUBLE_EQ(b.y0, -1.0);
  EXPECT_DOUBLE_EQ(b.y1, 1.0);
  EXPECT_NEAR(w.DistanceToWalls({5, 0.25}), 0.75, 1e-12);
  const auto hit = w.CastWalls({5, 0}, {1, 0});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->first, 6.0, 1e-12);
}

TEST(World, RecessedDoorAddsFloor) {
  const World w = ParseWorld(std::string(kHeader) +
                                 "corridors: [{from: [0, 0], to: [10, 0], width_m: 2, features: "
                                 "[{kind: door, side: left, at_m: 5, width_m: 1, recess_m: 0.3}]}]\n",
                             "door.yaml");
  EXPECT_TRUE(w.IsFree({5, 1.2}));
  EXPECT_FALSE(w.IsFree({5.7, 1.2}));
  ASSERT_EQ(w.decals.size(), 1u);
  EXPECT_DOUBLE_EQ(w.walls[w.decals[0].wall].coord, 1.3);
}

struct BadCase {
  const char* yaml;
  const char* expect;  // a piece of the message
};

class BadWorld : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadWorld, FailsNamingFileAndEntry) {
  const std::string msg = ErrorOf(GetParam().yaml);
  ASSERT_FALSE(msg.empty()) << "no error for: " << GetParam().yaml;
  EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find(GetParam().expect), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadWorld,
    ::testing::Values(
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], colour: red}]\n", "corridors[0]: unknown key 'colour'"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nrobot: {radius: 0.3}\n", "robot: unknown key 'radius'"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], width_m: 0}]\n", "width_m: must be positive"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], height_m: -2}]\n", "height_m: must be positive"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 3]}]\n", "must be axis-aligned"},
        BadCase{"corridors: [{name: a, from: [0, 0], to: [10, 0]}, {name: b, from: [0, 5], to: [10, 5]}]\n",
                "corridors[1] 'b' does not connect"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nobstacles: [{type: box, at: [5, 0.9], size: [0.4, 0.4, 0.5]}]\n",
                "obstacles[0] (box) at (5.00, 0.90) is inside or crosses a wall"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nobstacles: [{type: column, at: [5, 3]}]\n",
                "obstacles[0] (column)"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nobstacles: [{type: box, at: [5, 0], size: [0, 1, 1]}]\n",
                "sizes must be positive"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nrobot: {start: [5, 0.9, 0]}\n", "robot.start (5.00, 0.90)"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nrobot: {start: [5, 4, 0]}\n", "robot.start"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], features: [{kind: door, side: left, at_m: 10.8}]}]\n",
                "features[0]: runs past the end of its wall"},
        BadCase{"corridors: [{name: a, from: [0, 0], to: [10, 0], features: [{kind: poster, side: left, at_m: 5}]},"
                " {name: b, from: [5, 0], to: [5, 8]}]\n",
                "features[0]: the feature does not lie wholly on a wall"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], floor: marble}]\n", "unknown material 'marble'"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0], lights: {rows: centre, spacing_m: 0}}]\n", "spacing_m: must be positive"},
        BadCase{"corridors: []\n", "corridors"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\ncamera: {width: 0}\n", "camera.width"},
        BadCase{"corridors: [{from: [0, 0], to: [10, zero]}]\n", "is not a number"},
        BadCase{"corridors: [{from: [0, 0], to: [10, 0]}]\nfloor_items: [{type: paper, at: [5, 0.95]}]\n",
                "floor_items[0] (paper)"}));

TEST(World, WrongFormatAndMissingFile) {
  EXPECT_THROW(ParseWorld("format: other\ncorridors: []\n", "x.yaml"), Error);
  try {
    LoadWorld("/nonexistent/world.yaml");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/world.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace squint::sim
