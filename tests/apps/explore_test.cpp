// End-to-end `squint explore`: a short run writes summary.json (all keys), map.png and trace.csv;
// bad input (unknown world, non-positive minutes) is one clear error line and no output folder.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.hpp"

namespace {

using squint::test::CliResult;
using squint::test::RunSquint;

std::filesystem::path TempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("squint_apps_explore_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(ExploreCli, ShortRunWritesTheThreeOutputs) {
  const auto out = TempDir("short");
  const CliResult r = RunSquint("explore --world corridor-0 --minutes 0.5 --seed 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  std::ifstream js(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  for (const char* key : {"sim_seconds", "distance_m", "collisions", "coverage", "ends_detected", "turns", "frames",
                          "frames_fully_processed", "perception_cpu_seconds", "wall_seconds"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_NEAR(j["sim_seconds"].get<double>(), 30.0, 0.1);
  EXPECT_EQ(j["frames"].get<long>(), 900);
  EXPECT_GT(j["distance_m"].get<double>(), 1.0);
  EXPECT_TRUE(std::filesystem::exists(out / "map.png"));
  EXPECT_TRUE(std::filesystem::exists(out / "trace.csv"));
  std::filesystem::remove_all(out);
}

TEST(ExploreCli, UnknownWorldIsOneClearLine) {
  const auto out = TempDir("bad");
  const CliResult r = RunSquint("explore --world no-such-world --minutes 0.1 --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.all().find("squint: error:"), std::string::npos) << r.all();
  EXPECT_NE(r.all().find("no-such-world"), std::string::npos) << r.all();
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ExploreCli, NonPositiveMinutesIsRejected) {
  const auto out = TempDir("minutes");
  const CliResult r = RunSquint("explore --minutes 0 --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
