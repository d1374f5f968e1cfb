// End-to-end `squint sim`: a recorded sweep reads back as a sequence with ground truth and
// odometry, render and map write images, and a bad world file fails with one clear line.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_run.hpp"
#include "squint/io/sequence.hpp"

namespace {

namespace fs = std::filesystem;

using squint::test::CliResult;
using squint::test::RunSquint;

fs::path TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("squint_sim_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(SimCli, RecordSweepReadsBack) {
  const fs::path dir = TempDir("sweep");
  const CliResult r = RunSquint("sim record corridor-3 --protocol sweep --width 64 --height 48 --out " + (dir / "seq").string());
  ASSERT_EQ(r.code, 0) << r.all();
  const auto seq = squint::io::Sequence::Read(dir / "seq");
  ASSERT_EQ(seq.Size() % 41, 0u);
  EXPECT_EQ(seq.Camera().width, 64);
  EXPECT_TRUE(seq.HasOdometry());
  EXPECT_NEAR(*seq.Frames()[0].gt.heading_deg, -20.0, 1e-6);
  EXPECT_NEAR(*seq.Frames()[40].gt.heading_deg, 20.0, 1e-6);
  EXPECT_TRUE(seq.Frames()[0].gt.dist_end_m.has_value());
  EXPECT_EQ(seq.LoadImage(0).cols, 64);
  fs::remove_all(dir);
}

TEST(SimCli, CreepWritesLabels) {
  const fs::path dir = TempDir("creep");
  const CliResult r = RunSquint("sim record obstacle-course --protocol creep --width 64 --height 48 --out " + (dir / "seq").string());
  ASSERT_EQ(r.code, 0) << r.all();
  const auto seq = squint::io::Sequence::Read(dir / "seq");
  EXPECT_TRUE(seq.HasLabels());
  EXPECT_EQ(seq.LoadLabel(0).cols, 64);
  fs::remove_all(dir);
}

TEST(SimCli, RenderAndMap) {
  const fs::path dir = TempDir("render");
  CliResult r = RunSquint("sim render default --pose 5,0,10 --width 64 --height 48 --out " + (dir / "v.png").string());
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_TRUE(fs::exists(dir / "v.png"));
  r = RunSquint("sim map default --out " + (dir / "m.png").string());
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_TRUE(fs::exists(dir / "m.png"));
  r = RunSquint("sim render default --pose 5,9,0 --out " + (dir / "w.png").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.all().find("outside the floor"), std::string::npos) << r.all();
  fs::remove_all(dir);
}

TEST(SimCli, BadWorldFileFailsWithOneLine) {
  const fs::path dir = TempDir("bad");
  const fs::path world = dir / "bad.yaml";
  std::ofstream(world) << "format: squint-world/1\ncorridors: [{from: [0, 0], to: [10, 0]}]\n"
                          "obstacles: [{type: box, at: [5, 0.95]}]\n";
  const CliResult r = RunSquint("sim render " + world.string() + " --out " + (dir / "x.png").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.all().find("squint: error: " + world.string() + ": obstacles[0] (box)"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  fs::remove_all(dir);
}

}  // namespace
