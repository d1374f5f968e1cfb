// End-to-end `squint perceive`: the exact CSV header, one row per frame with stamps copied, the
// gate's skipped rows, the heading filter fed with the odometry's turn, and bad inputs giving one
// error line, a non-zero exit and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <opencv2/core.hpp>

#include "cli_run.hpp"
#include "squint/io/sequence.hpp"

namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader =
    "stamp,processed,heading_deg,dist_end_m,heading_entropy_deg,heading_symmetry_deg,heading_phase_deg,"
    "heading_vanishing_deg,heading_bright_deg,dist_ttc_m,dist_jeffrey_m,dist_entropy_m";

fs::path TempDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("squint_perceive_test_" + name);
  fs::remove_all(p);
  return p;
}

using squint::test::RunSquint;

// Five frames of a radial corridor pattern whose contrast changes from frame to frame (so the
// whole-glance entropy changes by more than the gate's 1%), except that frame 3 repeats frame 2.
fs::path WriteSequence(const std::string& name) {
  const fs::path dir = TempDir(name);
  squint::io::SequenceInfo info;
  info.name = name;
  info.camera.width = 160;
  info.camera.height = 120;
  info.camera.fx = info.camera.fy = 170.0;
  info.camera.cx = 79.5;
  info.camera.cy = 59.5;
  info.camera.height_m = 0.7;
  info.frame_rate_hz = 4.0;
  squint::io::SequenceWriter writer(dir, info);
  const double vx[] = {70.0, 80.0, 95.0, 95.0, 60.0};
  const double amplitude[] = {90.0, 70.0, 50.0, 50.0, 30.0};
  for (int i = 0; i < 5; ++i) {
    cv::Mat img(120, 160, CV_8UC1);
    for (int v = 0; v < 120; ++v)
      for (int u = 0; u < 160; ++u)
        img.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(110.0 + amplitude[i] * std::cos(6 * std::atan2(v - 59.5, u - vx[i])));
    squint::io::FrameRecord rec;
    rec.stamp = 0.25 * i + 0.125;
    writer.Add(rec, img);
  }
  writer.Finish();
  return dir;
}

std::vector<std::string> ReadLines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Split(const std::string& s) {
  std::vector<std::string> cells;
  std::stringstream ss(s);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  if (!s.empty() && s.back() == ',') cells.push_back("");
  return cells;
}

TEST(PerceiveCli, WritesOneRowPerFrameWithTheExactHeader) {
  const fs::path seq = WriteSequence("ok");
  const fs::path out = TempDir("ok.csv");
  ASSERT_EQ(RunSquint("perceive " + seq.string() + " --out " + out.string()).code, 0);
  const auto lines = ReadLines(out);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].rfind(std::string(kHeader), 0), 0u) << lines[0];
  const double stamps[] = {0.125, 0.375, 0.625, 0.875, 1.125};
  for (int i = 0; i < 5; ++i) {
    const auto cells = Split(lines[i + 1]);
    ASSERT_GE(cells.size(), 12u) << lines[i + 1];
    EXPECT_DOUBLE_EQ(std::stod(cells[0]), stamps[i]);
    for (const auto& c : cells) {
      EXPECT_EQ(c.find("nan"), std::string::npos) << lines[i + 1];
      EXPECT_EQ(c.find("inf"), std::string::npos) << lines[i + 1];
    }
    if (i == 3) {
      // Identical to frame 2: the gate skips it and every estimate is empty.
      EXPECT_EQ(cells[1], "0");
      for (int k = 2; k < 12; ++k) EXPECT_EQ(cells[k], "") << k;
    } else {
      EXPECT_EQ(cells[1], "1");
    }
  }
  // --no-gate processes every frame.
  ASSERT_EQ(RunSquint("perceive " + seq.string() + " --no-gate --out " + out.string()).code, 0);
  const auto all = ReadLines(out);
  ASSERT_EQ(all.size(), 6u);
  for (int i = 1; i <= 5; ++i) EXPECT_EQ(Split(all[i])[1], "1");
  // The vanishing point right of centre in frame 2 (u = 95) means a positive heading.
  const auto row2 = Split(all[3]);
  ASSERT_FALSE(row2[2].empty());
  EXPECT_GT(std::stod(row2[2]), 0.0);
}

TEST(PerceiveCli, BadInputsFailCleanlyWithoutOutput) {
  const fs::path out = TempDir("bad.csv");
  squint::test::CliResult r;
  // Missing input.
  r = RunSquint("perceive /nonexistent/seq --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(r.err.find("squint: error:"), std::string::npos) << r.err;
  // A sequence whose second image is corrupt.
  const fs::path seq = WriteSequence("corrupt");
  {
    std::ofstream f(seq / "images" / "000001.png", std::ios::trunc);
    f << "not a png";
  }
  r = RunSquint("perceive " + seq.string() + " --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(r.err.find("000001.png"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // A bad calibration file.
  const fs::path good = WriteSequence("good");
  const fs::path calib = TempDir("calib.yaml");
  {
    std::ofstream f(calib);
    f << "heading: {nonsense: 1}\n";
  }
  r = RunSquint("perceive " + good.string() + " --calib " + calib.string() + " --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(r.err.find("heading.nonsense"), std::string::npos) << r.err;
}

// Six identical frames with odometry turning `deg_per_frame` each (the view does not follow: only
// the heading filter's prediction differs between two such sequences).
fs::path WriteTurningSequence(const std::string& name, double deg_per_frame) {
  const fs::path dir = TempDir(name);
  squint::io::SequenceInfo info;
  info.name = name;
  info.camera.width = 160;
  info.camera.height = 120;
  info.camera.fx = info.camera.fy = 170.0;
  info.camera.cx = 79.5;
  info.camera.cy = 59.5;
  info.camera.height_m = 0.7;
  info.frame_rate_hz = 4.0;
  squint::io::SequenceWriter writer(dir, info);
  cv::Mat img(120, 160, CV_8UC1);
  for (int v = 0; v < 120; ++v)
    for (int u = 0; u < 160; ++u)
      img.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(110.0 + 80.0 * std::cos(6 * std::atan2(v - 59.5, u - 95.0)));
  for (int i = 0; i < 6; ++i) {
    squint::io::FrameRecord rec;
    rec.stamp = 0.25 * i;
    rec.odom = squint::Pose2{0.0, 0.0, i * deg_per_frame * M_PI / 180.0};
    writer.Add(rec, img);
  }
  writer.Finish();
  return dir;
}

TEST(PerceiveCli, HeadingFilterFollowsTheOdometryTurnAndTheInstantColumnKeepsThePerFrameFusion) {
  const fs::path calib = TempDir("filter.yaml");
  {
    std::ofstream f(calib);
    f << "heading: {filter: {enabled: true}}\n";
  }
  auto last_row = [&](const fs::path& seq, const std::string& extra) {
    const fs::path out = TempDir("filter.csv");
    EXPECT_EQ(RunSquint("perceive " + seq.string() + " --no-gate " + extra + " --out " + out.string()).code, 0);
    const auto lines = ReadLines(out);
    EXPECT_EQ(lines.size(), 7u);
    // heading_instant_deg, then the columns added after it (dist_floor_m).
    const auto header = Split(lines[0]);
    EXPECT_EQ(header.back(), "dist_floor_m");
    EXPECT_EQ(header[header.size() - 2], "heading_instant_deg");
    auto cells = Split(lines.back());
    EXPECT_EQ(cells.size(), header.size());
    cells.pop_back();  // heading_instant_deg last, as the checks below read it
    return cells;
  };
  const fs::path left = WriteTurningSequence("left", 3.0), right = WriteTurningSequence("right", -3.0);
  // Without the filter the heading is the per-frame fusion, whatever the odometry says.
  const auto plain = last_row(left, "");
  ASSERT_FALSE(plain[2].empty());
  EXPECT_EQ(plain[2], plain.back());
  EXPECT_EQ(last_row(right, "")[2], plain[2]);
  // With it, the same frames read further left while the odometry turns left than while it
  // turns right; the per-frame fusion stays the same.
  const auto l = last_row(left, "--calib " + calib.string()), r = last_row(right, "--calib " + calib.string());
  EXPECT_EQ(l.back(), plain.back());
  EXPECT_EQ(r.back(), plain.back());
  EXPECT_GT(std::stod(l[2]), std::stod(r[2]) + 1.0);
}

}  // namespace
