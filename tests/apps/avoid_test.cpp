// End-to-end tests of `squint avoid` and `squint eval avoid`: output format, atomic output and
// one-line errors for bad input.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using squint::test::CliResult;
using squint::test::RunSquint;

std::vector<std::string> Lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

fs::path TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("squint-avoid-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

const fs::path kSequence = fs::path(SQUINT_SHARED_DATA_DIR) / "obstacles-2-03";

TEST(AvoidCommandTest, WritesPolarAndSteeringTables) {
  if (!fs::exists(kSequence)) GTEST_SKIP() << "no shared data at " << kSequence;
  const fs::path out = TempDir("tables");
  const CliResult r = RunSquint("avoid " + kSequence.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  const auto polar = Lines(out / "polar.csv");
  const auto steering = Lines(out / "steering.csv");
  ASSERT_FALSE(polar.empty());
  ASSERT_FALSE(steering.empty());
  EXPECT_EQ(polar[0], "frame,bearing_deg,range_m");
  EXPECT_EQ(steering[0], "frame,steer_deg,stop");
  const std::size_t frames = steering.size() - 1;
  ASSERT_GT(frames, 0u);
  EXPECT_EQ(polar.size() - 1, frames * 36) << "one row per 5° sector of the semicircle per frame";
  // Each frame's sectors run from -87.5° to 87.5°; ranges lie within the ROI.
  std::map<std::string, int> rows_per_frame;
  for (std::size_t i = 1; i < polar.size(); ++i) {
    std::stringstream ss(polar[i]);
    std::string frame, bearing, range;
    std::getline(ss, frame, ',');
    std::getline(ss, bearing, ',');
    std::getline(ss, range, ',');
    const int k = rows_per_frame[frame]++;
    EXPECT_NEAR(std::stod(bearing), -87.5 + 5.0 * k, 1e-9) << polar[i];
    if (!range.empty()) {
      EXPECT_GT(std::stod(range), 0.0);
      EXPECT_LE(std::stod(range), 1.5);
    }
  }
  // steer_deg is empty exactly when stopping.
  for (std::size_t i = 1; i < steering.size(); ++i) {
    const std::string& l = steering[i];
    const bool stop = l.back() == '1';
    const bool empty_steer = l.find(",,") != std::string::npos;
    EXPECT_EQ(stop, empty_steer) << l;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "overlays"), fs::directory_iterator{}),
            static_cast<std::ptrdiff_t>(frames));
  fs::remove_all(out);
}

TEST(AvoidCommandTest, BadInputGivesOneLineAndNoOutput) {
  const fs::path out = TempDir("bad");
  CliResult r = RunSquint("avoid /nonexistent/sequence --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.all().find("squint: error:"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(out));

  const fs::path opts = fs::temp_directory_path() / ("squint-avoid-test-opts-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(opts) << "avoid:\n  polar: {sector_deg: 7}\n";
  r = RunSquint("avoid " + kSequence.string() + " --options " + opts.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.all().find(opts.string()), std::string::npos) << r.all();
  EXPECT_NE(r.all().find("sector_deg"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(out));
  fs::remove(opts);
}

// One options file with `ipt:` and `avoid:` sections serves both `squint obstacles` and
// `squint avoid` (the obstacles reader used to reject the `avoid:` section).
TEST(AvoidCommandTest, OneOptionsFileServesObstaclesAndAvoid) {
  if (!fs::exists(kSequence)) GTEST_SKIP() << "no shared data at " << kSequence;
  const fs::path dir = TempDir("shared-options");
  fs::create_directories(dir);
  const fs::path opts = dir / "options.yaml";
  std::ofstream(opts) << "ipt:\n  features: {detector: sift}\n  min_translation_m: 0.005\n"
                         "avoid:\n  polar: {roi_radius_m: 1.5}\n  gap: {margin_m: 0.05}\n";
  CliResult r = RunSquint("obstacles " + kSequence.string() + " --options " + opts.string() + " --out " +
                       (dir / "features.csv").string());
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_TRUE(fs::exists(dir / "features.csv"));
  r = RunSquint("avoid " + kSequence.string() + " --no-overlays --options " + opts.string() + " --out " +
                (dir / "avoid").string());
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_TRUE(fs::exists(dir / "avoid" / "steering.csv"));
  // A mistake in the IPT section is named for both commands.
  std::ofstream(opts) << "ipt:\n  features: {detector: surf}\navoid: {}\n";
  for (const std::string cmd : {"obstacles", "avoid"}) {
    r = RunSquint(cmd + " " + kSequence.string() + " --options " + opts.string() + " --out " + (dir / "x").string());
    EXPECT_EQ(r.code, 1) << cmd;
    EXPECT_NE(r.all().find("(section ipt): `features.detector`"), std::string::npos) << cmd << ": " << r.all();
    EXPECT_FALSE(fs::exists(dir / "x")) << cmd;
  }
  fs::remove_all(dir);
}

TEST(EvalAvoidCommandTest, ReportsTheTargets) {
  if (!fs::exists(kSequence)) GTEST_SKIP() << "no shared data at " << kSequence;
  const fs::path out = TempDir("eval");
  const CliResult r = RunSquint("eval avoid " + kSequence.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.all().find("targets: sector agreement"), std::string::npos) << r.all();
  EXPECT_TRUE(fs::exists(out / "avoid_eval.json"));
  EXPECT_TRUE(fs::exists(out / "frames.csv"));
  fs::remove_all(out);
}

}  // namespace
