// End-to-end `squint obstacles` / `squint eval obstacles` on a shared obstacle sequence (skipped
// when ../shared/data is absent), and the CLI's errors for bad inputs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;

// Exit code of `squint ARGS`; its standard error in *err when given.
int RunSquint(const std::string& args, std::string* err = nullptr) {
  const squint::test::CliResult r = squint::test::RunSquint(args);
  if (err) *err = r.err;
  return r.code;
}

fs::path Sequence() { return fs::path(SQUINT_SHARED_DATA_DIR) / "obstacles-2-00"; }

TEST(ObstaclesCli, WritesTheFixedHeaderAndValidRows) {
  if (!fs::exists(Sequence())) GTEST_SKIP() << "no shared data";
  const fs::path out = fs::temp_directory_path() / "squint_obstacles_test.csv";
  fs::remove(out);
  ASSERT_EQ(RunSquint("obstacles " + Sequence().string() + " --detector klt --out " + out.string()), 0);
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("frame,u,v,discrepancy_m,class", 0), 0u) << line;
  int rows = 0, above = 0;
  while (std::getline(in, line)) {
    ++rows;
    std::stringstream ss(line);
    std::string frame, u, v, d, cls;
    std::getline(ss, frame, ',');
    std::getline(ss, u, ',');
    std::getline(ss, v, ',');
    std::getline(ss, d, ',');
    std::getline(ss, cls, ',');
    const int f = std::stoi(frame);
    EXPECT_GE(f, 1);
    EXPECT_LE(f, 23);
    EXPECT_TRUE(cls == "ground" || cls == "obstacle") << line;
    if (d.empty()) {
      ++above;
      EXPECT_EQ(cls, "obstacle") << "features above the horizon are obstacles: " << line;
    }
  }
  EXPECT_GT(rows, 23 * 20);
  EXPECT_GT(above, 0);
}

TEST(ObstaclesCli, EvalWritesReportAndLearnedOptionsThatObstaclesReads) {
  if (!fs::exists(Sequence())) GTEST_SKIP() << "no shared data";
  const fs::path dir = fs::temp_directory_path() / "squint_eval_obstacles_test";
  fs::remove_all(dir);
  const fs::path second = fs::path(SQUINT_SHARED_DATA_DIR) / "obstacles-2-01";
  ASSERT_EQ(RunSquint("eval obstacles " + Sequence().string() + " " + second.string() + " --detector klt --out " + dir.string()), 0);
  for (const char* f : {"roc.png", "report.json", "report.md", "obstacles_options.yaml", "samples.csv"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const fs::path out = dir / "features.csv";
  EXPECT_EQ(RunSquint("obstacles " + Sequence().string() + " --options " + (dir / "obstacles_options.yaml").string() +
                " --out " + out.string()),
            0);
  EXPECT_TRUE(fs::exists(out));
}

TEST(ObstaclesCli, BadInputsGiveOneLineErrors) {
  std::string err;
  const fs::path bad = fs::temp_directory_path() / "squint_bad_obstacles.yaml";
  std::ofstream(bad) << "features: {detector: surf}\n";
  const fs::path seq = fs::exists(Sequence()) ? Sequence() : fs::path("/nonexistent");
  EXPECT_EQ(RunSquint("obstacles " + seq.string() + " --options " + bad.string() + " --out /tmp/x.csv", &err), 1);
  EXPECT_NE(err.find("features.detector"), std::string::npos) << err;
  EXPECT_EQ(RunSquint("obstacles /nonexistent/seq --out /tmp/x.csv", &err), 1);
  EXPECT_NE(err.find("squint: error:"), std::string::npos) << err;
  if (fs::exists(Sequence())) {
    EXPECT_EQ(RunSquint("obstacles " + Sequence().string() + " --detector surf --out /tmp/x.csv", &err), 1);
    EXPECT_NE(err.find("--detector"), std::string::npos) << err;
    const fs::path never = fs::temp_directory_path() / "squint_eval_obstacles_bad_lambda";
    fs::remove_all(never);
    EXPECT_EQ(RunSquint("eval obstacles " + Sequence().string() + " --unclassified-cost -1 --out " + never.string(), &err),
              1);
    EXPECT_NE(err.find("--unclassified-cost"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(never));  // no partial output
  }
}

}  // namespace
