// Run-by-run comparison of seeded exploration runs: known answers from constructed runs.csv
// files (per-world means, changed runs, runs failing in one set only, the sign test), the two
// layouts (one runs.csv, seed-S folders), and bad input.
#include "squint/eval/explore_compare.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

#include "squint/core/error.hpp"

namespace squint::eval {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader =
    "world,start,x_m,y_m,yaw_deg,sim_seconds,distance_m,coverage,ends_detected,turns,collisions,proceeded,"
    "setoff_s,setoff_axis_error_deg,axis_error_p90_deg,axis_error_over_10deg,first_collision_s,first_hit,"
    "mirror_scans,contacts_felt,near_edges\n";

fs::path TempDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("squint_explore_compare_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

void Write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

// One runs.csv row: the start pose is (start, 0, 0) so that both sets agree unless a test says not.
std::string Row(const std::string& world, int start, double distance, double coverage, int collisions,
                const std::string& first_s = "", const std::string& first_hit = "", double x = -1.0) {
  const double sx = x >= 0.0 ? x : start;
  return world + "," + std::to_string(start) + "," + std::to_string(sx) + ",0.000,0.00,180.0," + std::to_string(distance) +
         "," + std::to_string(coverage) + ",1,1," + std::to_string(collisions) + ",1,0.2,0.1,1.0,0.0," + first_s + "," +
         first_hit + ",0,0,0\n";
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ExploreCompare, SignTestKnownValues) {
  EXPECT_DOUBLE_EQ(SignTestP(0, 0), 1.0);
  EXPECT_NEAR(SignTestP(2, 0), 0.5, 1e-12);       // 2 · (1/4)
  EXPECT_NEAR(SignTestP(0, 5), 0.0625, 1e-12);    // 2 · (1/32)
  EXPECT_NEAR(SignTestP(3, 1), 0.625, 1e-12);     // 2 · (1 + 4)/16
  EXPECT_NEAR(SignTestP(10, 0), 2.0 / 1024.0, 1e-12);
  EXPECT_DOUBLE_EQ(SignTestP(4, 4), 1.0);         // capped at 1
  EXPECT_DOUBLE_EQ(SignTestP(1, 3), SignTestP(3, 1));
}

TEST(ExploreCompare, SeedFoldersMatchedRunByRunWithKnownFigures) {
  const fs::path base = TempDir("base"), next = TempDir("next");
  // Seed 1: world a, starts 0 and 1; world b, start 0. Seed 2: world a, start 0.
  Write(base / "seed-1" / "runs.csv",
        std::string(kHeader) + Row("a", 0, 10.0, 0.50, 0) + Row("a", 1, 20.0, 0.70, 3, "12.50", "wall") +
            Row("b", 0, 30.0, 0.90, 0));
  Write(base / "seed-2" / "runs.csv", std::string(kHeader) + Row("a", 0, 40.0, 0.30, 0));
  // NEW: a/0 of seed 1 unchanged; a/1 cleared; b/0 newly failing; seed 2's a/0 unchanged.
  Write(next / "seed-1" / "runs.csv",
        std::string(kHeader) + Row("a", 0, 10.0, 0.50, 0) + Row("a", 1, 22.0, 0.80, 0) +
            Row("b", 0, 28.0, 0.60, 2, "40.00", "obstacles[1] (box)"));
  Write(next / "seed-2" / "runs.csv", std::string(kHeader) + Row("a", 0, 40.0, 0.30, 0));
  // A log beside the folders, as tools/eval_explore_seeds.sh leaves them, is not a set.
  Write(base / "seed-1.log", "seed 1\n");

  const auto b = LoadExploreRuns(base);
  const auto n = LoadExploreRuns(next);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[0].set, "seed-1");
  EXPECT_EQ(b[3].set, "seed-2");
  EXPECT_EQ(b[1].first_hit, "wall");
  EXPECT_DOUBLE_EQ(b[1].first_collision_s, 12.5);
  EXPECT_TRUE(std::isnan(b[0].first_collision_s));

  const ExploreComparison c = CompareExploreRuns(b, n);
  EXPECT_EQ(c.all.runs, 4);
  EXPECT_EQ(c.all.changed, 2);
  EXPECT_EQ(c.only_in_base, 0);
  EXPECT_EQ(c.only_in_new, 0);
  ASSERT_EQ(c.worlds.size(), 2u);
  EXPECT_EQ(c.worlds[0].world, "a");
  EXPECT_EQ(c.worlds[0].runs, 3);
  EXPECT_EQ(c.worlds[0].changed, 1);
  EXPECT_NEAR(c.worlds[0].base_coverage, (0.5 + 0.7 + 0.3) / 3.0, 1e-9);
  EXPECT_NEAR(c.worlds[0].new_coverage, (0.5 + 0.8 + 0.3) / 3.0, 1e-9);
  EXPECT_NEAR(c.worlds[0].base_distance_m, 70.0 / 3.0, 1e-9);
  EXPECT_NEAR(c.worlds[0].new_distance_m, 72.0 / 3.0, 1e-9);
  EXPECT_EQ(c.worlds[0].base_failed, 1);
  EXPECT_EQ(c.worlds[0].new_failed, 0);
  EXPECT_EQ(c.worlds[1].world, "b");
  EXPECT_EQ(c.worlds[1].base_failed, 0);
  EXPECT_EQ(c.worlds[1].new_failed, 1);
  EXPECT_EQ(c.all.base_failed, 1);
  EXPECT_EQ(c.all.new_failed, 1);
  // Paired differences 0, +0.1, -0.3, 0: mean -0.05, sample variance (0.1 - 0.2² / 4) / 3 = 0.03,
  // interval 1.96 sd / sqrt(4).
  EXPECT_NEAR(c.coverage_diff_mean, -0.05, 1e-9);
  EXPECT_NEAR(c.coverage_diff_ci95, 1.96 * std::sqrt(0.03) / 2.0, 1e-9);
  ASSERT_EQ(c.newly_failed.size(), 1u);
  EXPECT_EQ(c.newly_failed[0].second.world, "b");
  ASSERT_EQ(c.cleared.size(), 1u);
  EXPECT_EQ(c.cleared[0].first.start, 1);
  EXPECT_DOUBLE_EQ(c.failure_sign_p, 1.0);

  const std::string report = FormatExploreComparison(c, "base", "next");
  EXPECT_NE(report.find("| a | 3 | 1 | 0.5000 | 0.5333 | 23.3 | 24.0 | 1 | 0 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| all | 4 | 2 |"), std::string::npos) << report;
  EXPECT_NE(report.find("- seed-1 b start 0: 2 steps in contact, first at 40.0 s, met obstacles[1] (box)"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("- seed-1 a start 1: 3 steps in contact, first at 12.5 s, met wall"), std::string::npos)
      << report;
  fs::remove_all(base);
  fs::remove_all(next);
}

TEST(ExploreCompare, OneRunsCsvAgainstItsFolderAndRunsInOneSetOnly) {
  const fs::path dir = TempDir("single");
  Write(dir / "base" / "runs.csv", std::string(kHeader) + Row("a", 0, 10.0, 0.5, 0) + Row("a", 1, 10.0, 0.5, 0));
  Write(dir / "new.csv", std::string(kHeader) + Row("a", 0, 10.0, 0.5, 0) + Row("c", 0, 5.0, 0.1, 0));
  const ExploreComparison c = CompareExploreRuns(LoadExploreRuns(dir / "base"), LoadExploreRuns(dir / "new.csv"));
  EXPECT_EQ(c.all.runs, 1);
  EXPECT_EQ(c.all.changed, 0);
  EXPECT_EQ(c.only_in_base, 1);
  EXPECT_EQ(c.only_in_new, 1);
  EXPECT_DOUBLE_EQ(c.coverage_diff_mean, 0.0);
  EXPECT_TRUE(std::isnan(c.coverage_diff_ci95));  // one run: no interval
  fs::remove_all(dir);
}

TEST(ExploreCompare, OnlyTheColumnsBothFilesHaveDecideAChange) {
  const fs::path dir = TempDir("columns");
  // An older runs.csv without the last three columns.
  Write(dir / "old.csv",
        "world,start,x_m,y_m,yaw_deg,sim_seconds,distance_m,coverage,ends_detected,turns,collisions\n"
        "a,0,0.000000,0.000,0.00,180.0,10.000000,0.500000,1,1,0\n");
  Write(dir / "new.csv", std::string(kHeader) + Row("a", 0, 10.0, 0.5, 0));
  EXPECT_EQ(CompareExploreRuns(LoadExploreRuns(dir / "old.csv"), LoadExploreRuns(dir / "new.csv")).all.changed, 0);
  Write(dir / "new2.csv", std::string(kHeader) + Row("a", 0, 10.5, 0.5, 0));
  EXPECT_EQ(CompareExploreRuns(LoadExploreRuns(dir / "old.csv"), LoadExploreRuns(dir / "new2.csv")).all.changed, 1);
  fs::remove_all(dir);
}

TEST(ExploreCompare, BadInputNamesTheFileAndTheRun) {
  const fs::path dir = TempDir("bad");
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "nothing"); }).find("no such file or folder"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir); }).find("no runs.csv and no seed-S folders"), std::string::npos);
  fs::create_directories(dir / "set" / "seed-3");
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "set"); }).find("seed-3: no runs.csv"), std::string::npos);

  Write(dir / "header_only.csv", kHeader);
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "header_only.csv"); }).find("no runs"), std::string::npos);
  Write(dir / "no_coverage.csv", "world,start,x_m,y_m,yaw_deg,distance_m,collisions\na,0,0,0,0,1,0\n");
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "no_coverage.csv"); }).find("missing required column 'coverage'"),
            std::string::npos);
  Write(dir / "text.csv", std::string(kHeader) + "a,0,0,0,0,180,ten,0.5,1,1,0,1,,,,,,,0,0,0\n");
  const std::string text = ErrorOf([&] { LoadExploreRuns(dir / "text.csv"); });
  EXPECT_NE(text.find("text.csv: line 2: column 'distance_m': 'ten' is not a finite number"), std::string::npos) << text;
  Write(dir / "half.csv", std::string(kHeader) + "a,0.5,0,0,0,180,1,0.5,1,1,0,1,,,,,,,0,0,0\n");
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "half.csv"); }).find("'0.5' is not a whole number"), std::string::npos);
  Write(dir / "cov.csv", std::string(kHeader) + Row("a", 0, 1.0, 1.5, 0));
  EXPECT_NE(ErrorOf([&] { LoadExploreRuns(dir / "cov.csv"); }).find("outside [0, 1]"), std::string::npos);
  Write(dir / "twice.csv", std::string(kHeader) + Row("a", 0, 1.0, 0.5, 0) + Row("a", 0, 2.0, 0.5, 0));
  const std::string twice = ErrorOf([&] { LoadExploreRuns(dir / "twice.csv"); });
  EXPECT_NE(twice.find("twice.csv:3: a start 0 appears twice (first at"), std::string::npos) << twice;

  // The same run from another pose: not the same starts.
  Write(dir / "p1.csv", std::string(kHeader) + Row("a", 0, 1.0, 0.5, 0, "", "", 1.0));
  Write(dir / "p2.csv", std::string(kHeader) + Row("a", 0, 1.0, 0.5, 0, "", "", 2.0));
  const std::string pose =
      ErrorOf([&] { CompareExploreRuns(LoadExploreRuns(dir / "p1.csv"), LoadExploreRuns(dir / "p2.csv")); });
  EXPECT_NE(pose.find("a start 0 starts at (1.000, 0.000, 0.00 deg)"), std::string::npos) << pose;
  EXPECT_NE(pose.find("not the same starts"), std::string::npos) << pose;
  // Nothing shared.
  Write(dir / "other.csv", std::string(kHeader) + Row("z", 0, 1.0, 0.5, 0));
  EXPECT_NE(ErrorOf([&] { CompareExploreRuns(LoadExploreRuns(dir / "p1.csv"), LoadExploreRuns(dir / "other.csv")); })
                .find("share no run"),
            std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace squint::eval
