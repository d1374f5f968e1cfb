// The closed loop on small worlds: a short corridor the robot must drive to its far end without
// collision; a closed box where exploration cannot proceed (a clear outcome, bounded time);
// coverage and seeded starts on known geometry.
#include "squint/eval/explore_run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::eval {
namespace {

// A 14 m dead-end corridor with a centre row of lights; the robot starts 1.5 m from one end.
constexpr const char* kShortCorridor = R"(
format: squint-world/1
name: short
camera: {height_m: 0.6, pitch_deg: -3.0, hfov_deg: 60.0, width: 320, height: 240}
robot: {radius_m: 0.25, max_speed_mps: 0.6, max_turn_rate_dps: 90, start: [1.5, 0.0, 0.0]}
corridors:
  - name: main
    from: [0, 0]
    to: [14, 0]
    width_m: 2.0
    height_m: 2.8
    floor: tiles
    wall: paint
    lights: {rows: centre, spacing_m: 3.0, size_m: [1.2, 0.3]}
    features:
      - {kind: door, side: left, at_m: 4, repeat_every_m: 5, count: 2}
      - {kind: door, side: right, at_m: 6}
)";

// A 2 m × 2 m closed box: nowhere to go.
constexpr const char* kBox = R"(
format: squint-world/1
name: box
camera: {height_m: 0.6, pitch_deg: -3.0, hfov_deg: 60.0, width: 320, height: 240}
robot: {radius_m: 0.25, max_speed_mps: 0.6, max_turn_rate_dps: 90, start: [0.5, 0.0, 0.0]}
corridors:
  - name: cell
    from: [0, 0]
    to: [1, 0]
    width_m: 2.0
    height_m: 2.8
    lights: {rows: centre, spacing_m: 3.0, size_m: [0.6, 0.3]}
)";

// One minute in the short corridor, seed 3 (with its trace), run once for the tests that read it.
const ExploreRunResult& ShortCorridorRun() {
  static const ExploreRunResult run = [] {
    ExploreRunOptions opt;
    opt.minutes = 1.0;
    opt.seed = 3;
    return RunExplore(sim::ParseWorld(kShortCorridor, "test:short"), opt);
  }();
  return run;
}

TEST(ExploreRun, ShortCorridorReachesTheFarEndWithoutCollision) {
  const ExploreRunResult& run = ShortCorridorRun();
  double max_x = 0.0;
  for (const Pose2& p : run.true_path) max_x = std::max(max_x, p.x);
  // The far end wall is at x = 15 (the floor reaches width/2 beyond the end point).
  EXPECT_GT(max_x, 12.0) << run.summary.outcome;
  EXPECT_EQ(run.summary.collisions, 0) << run.summary.outcome;
  EXPECT_GE(run.summary.ends_detected, 1);
  EXPECT_GE(run.summary.turns, 1);
  EXPECT_TRUE(run.summary.proceeded);
  EXPECT_EQ(run.summary.frames, 1800);
  EXPECT_LT(run.summary.frames_fully_processed, run.summary.frames);
  EXPECT_GT(run.summary.coverage, 0.8);
  EXPECT_EQ(run.trace.size(), 1800u);
}

// The same corridor with a box standing left of the centre line (0.9 m of free floor to its right).
constexpr const char* kBoxInCorridor = R"(
format: squint-world/1
name: boxed
camera: {height_m: 0.6, pitch_deg: -3.0, hfov_deg: 60.0, width: 320, height: 240}
robot: {radius_m: 0.25, max_speed_mps: 0.6, max_turn_rate_dps: 90, start: [1.5, 0.0, 0.0]}
corridors:
  - name: main
    from: [0, 0]
    to: [14, 0]
    width_m: 2.0
    height_m: 2.8
    floor: tiles
    wall: paint
    lights: {rows: centre, spacing_m: 3.0, size_m: [1.2, 0.3]}
obstacles:
  - {type: box, at: [6.0, 0.35], size: [0.5, 0.6, 0.7]}
)";

TEST(ExploreRun, VisualSonarKeepsClearOfABoxAndOfAWallFacedAtTheStart) {
  const sim::World boxed = sim::ParseWorld(kBoxInCorridor, "test:boxed");
  ExploreRunOptions opt;
  opt.minutes = 1.0;
  opt.keep_trace = false;
  const ExploreRunResult run = RunExplore(boxed, opt);
  EXPECT_EQ(run.summary.collisions, 0) << run.summary.outcome;
  double max_x = 0.0;
  for (const Pose2& p : run.true_path) max_x = std::max(max_x, p.x);
  EXPECT_GT(max_x, 7.0) << "did not get past the box: " << run.summary.outcome;
  // Facing the side wall 0.6 m away (its disc 0.35 m from it), in the plain short corridor.
  const sim::World world = sim::ParseWorld(kShortCorridor, "test:short");
  opt.start = Pose2{5.0, 0.4, kPi / 2};
  const ExploreRunResult facing = RunExplore(world, opt);
  EXPECT_EQ(facing.summary.collisions, 0) << facing.summary.outcome;
  EXPECT_TRUE(facing.summary.proceeded) << facing.summary.outcome;
}

// The obstacle pipeline in the loop (issue 7): the box reaches into the path of a robot on the
// centre line; the pipeline must see it there and the override steer; no collision. The explorer
// as the override was tuned with (before session 12: the per-frame axis, the side walls'
// centring; the pipeline is off by default). With session 12's defaults the sonar passes the box
// before the override acts, and without the sonar the heading filter's axis takes the robot into
// the box (28 steps in contact; docs/explore.md, session 12).
TEST(ExploreRun, ObstaclePipelineSeesTheBoxAcrossThePathAndTheRobotPassesIt) {
  const sim::World boxed = sim::ParseWorld(kBoxInCorridor, "test:boxed");
  ExploreRunOptions opt;
  opt.minutes = 0.5;
  opt.keep_trace = false;
  opt.obstacle_pipeline = true;  // off by default
  opt.explorer.filtered_axis_gain = 0.0;
  opt.explorer.light_centre_gain = 0.0;
  opt.explorer.branch_line_tolerance_m = 0.0;
  opt.explorer.mouth_centre_min_m = 0.0;
  opt.explorer.sonar_open_min_entropy_ratio = 0.0;
  for (bool sonar : {true, false}) {
    opt.visual_sonar = sonar;
    const ExploreRunResult run = RunExplore(boxed, opt);
    const ExploreSummary& s = run.summary;
    EXPECT_EQ(s.collisions, 0) << "sonar " << sonar << ": " << s.outcome;
    double max_x = 0.0;
    for (const Pose2& p : run.true_path) max_x = std::max(max_x, p.x);
    // Without the sonar the glance's end detection reads the box as the corridor's end and turns
    // back in front of it (no collision); with it the robot passes.
    if (sonar) {
      EXPECT_GT(max_x, 7.0) << "did not get past the box: " << s.outcome;
    }
    EXPECT_GT(s.ipt_classified, 10) << s.outcome;
    EXPECT_GT(s.advice_in_path, 0) << s.outcome;
    EXPECT_GT(s.override_frames, 0) << s.outcome;
    EXPECT_GT(s.ipt_cpu_seconds, 0.0);
    EXPECT_LE(s.ipt_cpu_seconds, s.perception_cpu_seconds);
  }
  // Deterministic with the pipeline on: the same run twice.
  opt.visual_sonar = true;
  opt.minutes = 0.2;
  const ExploreRunResult a = RunExplore(boxed, opt);
  const ExploreRunResult b = RunExplore(boxed, opt);
  EXPECT_EQ(a.true_path.back().x, b.true_path.back().x);
  EXPECT_EQ(a.true_path.back().yaw, b.true_path.back().yaw);
  EXPECT_EQ(a.summary.ipt_classified, b.summary.ipt_classified);
  EXPECT_EQ(a.summary.outcome, b.summary.outcome);
  // Off: no pairs, no override.
  opt.minutes = 0.5;
  opt.obstacle_pipeline = false;
  const ExploreRunResult off = RunExplore(boxed, opt);
  EXPECT_EQ(off.summary.ipt_pairs, 0);
  EXPECT_EQ(off.summary.override_frames, 0);
}

TEST(ExploreRun, SameSeedSameRun) {
  const sim::World world = sim::ParseWorld(kShortCorridor, "test:short");
  ExploreRunOptions opt;
  opt.minutes = 0.3;
  const ExploreRunResult a = RunExplore(world, opt);
  const ExploreRunResult b = RunExplore(world, opt);
  ASSERT_EQ(a.true_path.size(), b.true_path.size());
  EXPECT_EQ(a.true_path.back().x, b.true_path.back().x);
  EXPECT_EQ(a.true_path.back().yaw, b.true_path.back().yaw);
  EXPECT_EQ(SummaryJson(a.summary).substr(0, 200), SummaryJson(b.summary).substr(0, 200));
}

TEST(ExploreRun, ClosedBoxEndsWithAClearMessageWithinTheBudget) {
  const sim::World world = sim::ParseWorld(kBox, "test:box");
  ExploreRunOptions opt;
  opt.minutes = 0.5;
  const ExploreRunResult run = RunExplore(world, opt);
  EXPECT_NEAR(run.summary.sim_seconds, 30.0, 0.1);
  EXPECT_FALSE(run.summary.proceeded);
  EXPECT_NE(run.summary.outcome.find("could not proceed"), std::string::npos) << run.summary.outcome;
  // The map is still drawn.
  const cv::Mat map = DrawExploreMap(world, run);
  EXPECT_GT(map.cols, 10);
  EXPECT_GT(map.rows, 10);
}

TEST(ExploreRun, CoverageOfKnownPaths) {
  const sim::World world = sim::ParseWorld(kShortCorridor, "test:short");
  std::vector<Pose2> full, half, off;
  for (double x = 0.0; x <= 14.0; x += 0.05) full.push_back({x, 0.0, 0.0});
  for (double x = 0.0; x <= 7.0; x += 0.05) half.push_back({x, 0.3, 0.0});
  for (double x = 0.0; x <= 14.0; x += 0.05) off.push_back({x, 1.5, 0.0});  // outside half the width
  EXPECT_NEAR(CorridorCoverage(world, full), 1.0, 1e-9);
  EXPECT_NEAR(CorridorCoverage(world, half), 0.5 + 0.95 / 14.0, 0.02);  // reach: sqrt(1 - 0.3²) ahead
  EXPECT_NEAR(CorridorCoverage(world, off), 0.0, 1e-9);
  EXPECT_EQ(CorridorCoverage(world, {}), 0.0);
}

TEST(ExploreRun, SeededStartsAreFreeDeterministicAndIncludeTheHardCases) {
  const sim::World world = sim::LoadWorld("default");
  const std::vector<Pose2> a = SeededStarts(world, 10, 5);
  const std::vector<Pose2> b = SeededStarts(world, 10, 5);
  ASSERT_EQ(a.size(), 10u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].yaw, b[i].yaw);
    EXPECT_GT(world.DistanceToWalls(a[i].Translation()), world.robot.radius_m) << i;
  }
  EXPECT_EQ(a[0].x, world.start.x);
  // Start 1 faces a side wall: its yaw is perpendicular to some corridor axis (a multiple of 90°
  // away from the start's axis-aligned corridors) and start 2 is within 0.2 m of the wall clearance.
  EXPECT_NEAR(std::abs(std::remainder(RadToDeg(a[1].yaw), 90.0)), 0.0, 1e-6);
  EXPECT_LT(world.DistanceToWalls(a[2].Translation()), world.robot.radius_m + 0.2);
}

TEST(ExploreRun, OutputsAreWritten) {
  const sim::World world = sim::ParseWorld(kShortCorridor, "test:short");
  ExploreRunOptions opt;
  opt.minutes = 0.2;
  const ExploreRunResult run = RunExplore(world, opt);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "squint_explore_run_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  WriteExploreOutputs(dir, world, run);
  EXPECT_TRUE(std::filesystem::exists(dir / "map.png"));
  std::ifstream csv(dir / "trace.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t_s,true_x_m,true_y_m,true_yaw_deg,odom_x_m", 0), 0u);
  std::ifstream js(dir / "summary.json");
  const std::string text((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  for (const char* key : {"sim_seconds", "distance_m", "collisions", "coverage", "ends_detected", "turns", "frames",
                          "frames_fully_processed", "perception_cpu_seconds", "wall_seconds", "setoff_seconds",
                          "setoff_axis_error_deg", "axis_error_p90_deg", "axis_error_over_10deg", "first_collision_s",
                          "first_hit"})
    EXPECT_NE(text.find(std::string("\"") + key + "\""), std::string::npos) << key;
  std::filesystem::remove_all(dir);
}

// The axis figures (setoff_*, axis_error_*) are the trace's: the first set-off's row, and the rows
// spent following. In the short corridor, set off along the axis, they are small.
TEST(ExploreRun, AxisErrorFiguresAreTheTracesAndSmallInAPlainCorridor) {
  const ExploreRunResult& run = ShortCorridorRun();
  const ExploreSummary& s = run.summary;
  ASSERT_FALSE(std::isnan(s.setoff_seconds));
  const auto first = std::find_if(run.marks.begin(), run.marks.end(), [](const ExploreMark& m) {
    return m.event.kind == explore::ExploreEvent::Kind::kScanDone;
  });
  ASSERT_NE(first, run.marks.end());
  EXPECT_EQ(s.setoff_seconds, first->event.stamp_s);
  std::vector<double> errs;
  bool found_setoff = false;
  for (const ExploreTraceRow& r : run.trace) {
    const double err = std::remainder(r.true_heading_deg - r.heading_est_deg, 90.0);
    if (r.t_s == s.setoff_seconds) {
      EXPECT_DOUBLE_EQ(s.setoff_axis_error_deg, err);
      found_setoff = true;
    }
    if (r.state == explore::ExploreState::kFollow && !std::isnan(r.true_heading_deg)) errs.push_back(std::abs(err));
  }
  EXPECT_TRUE(found_setoff);
  ASSERT_GT(errs.size(), 100u);
  const double over = static_cast<double>(std::count_if(errs.begin(), errs.end(), [](double e) { return e > 10.0; }));
  EXPECT_DOUBLE_EQ(s.axis_error_over_10deg, over / static_cast<double>(errs.size()));
  std::sort(errs.begin(), errs.end());
  EXPECT_DOUBLE_EQ(s.axis_error_p90_deg, errs[static_cast<std::size_t>(0.9 * static_cast<double>(errs.size() - 1))]);
  EXPECT_LT(std::abs(s.setoff_axis_error_deg), 3.0);
  EXPECT_LT(s.axis_error_p90_deg, 5.0);
  EXPECT_LT(s.axis_error_over_10deg, 0.02);
}

TEST(ExploreRun, InvalidOptionsAreAClearError) {
  const sim::World world = sim::ParseWorld(kShortCorridor, "test:short");
  ExploreRunOptions opt;
  opt.minutes = -1.0;
  EXPECT_THROW(RunExplore(world, opt), Error);
}

}  // namespace
}  // namespace squint::eval
