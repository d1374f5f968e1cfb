// End to end: `squint calibrate` refuses inputs it cannot fit (no YAML written), and on the shared
// data writes a file that `perceive` and `eval corridor` read back.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>
#include <string>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "squint/io/sequence.hpp"

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using squint::test::CliResult;
using squint::test::RunSquint;

// A small sequence of textured frames; `heading`/`dist` give each frame's truth (none = column absent).
fs::path WriteSequence(const std::string& name, bool with_heading, bool constant_heading, bool constant_dist) {
  const fs::path dir = fs::temp_directory_path() / ("squint_calibrate_test_" + name);
  fs::remove_all(dir);
  squint::io::SequenceInfo info;
  info.name = name;
  info.camera.width = 64;
  info.camera.height = 48;
  info.camera.fx = info.camera.fy = 60.0;
  info.camera.cx = 31.5;
  info.camera.cy = 23.5;
  info.camera.height_m = 0.7;
  info.frame_rate_hz = 4.0;
  squint::io::SequenceWriter w(dir, info);
  cv::RNG rng(11);
  for (int i = 0; i < 30; ++i) {
    cv::Mat img(48, 64, CV_8UC1);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    squint::io::FrameRecord rec;
    rec.stamp = 0.25 * i;
    rec.odom = squint::Pose2{0.1 * i, 0.0, 0.0};
    if (with_heading) rec.gt.heading_deg = constant_heading ? 2.0 : -15.0 + i;
    rec.gt.dist_end_m = constant_dist ? 4.0 : 10.0 - 0.1 * i;
    w.Add(rec, img);
  }
  w.Finish();
  return dir;
}

TEST(CalibrateCli, MissingHeadingColumnIsAnErrorAndWritesNothing) {
  const fs::path seq = WriteSequence("nohead", false, false, false);
  const fs::path out = fs::temp_directory_path() / "squint_calibrate_test_nohead.yaml";
  fs::remove(out);
  const CliResult r = RunSquint("calibrate " + seq.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.all();
  EXPECT_NE(r.all().find("frames.csv: no gt_heading_deg values"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(seq);
}

TEST(CalibrateCli, AllHeadingsEqualIsSingular) {
  const fs::path seq = WriteSequence("onehead", true, true, false);
  const fs::path out = fs::temp_directory_path() / "squint_calibrate_test_onehead.yaml";
  fs::remove(out);
  const CliResult r = RunSquint("calibrate " + seq.string() + " --only heading --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.all();
  EXPECT_NE(r.all().find("singular calibration: the true headings"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(seq);
}

TEST(CalibrateCli, OneDistanceOnlyIsSingular) {
  const fs::path seq = WriteSequence("onedist", true, false, true);
  const fs::path out = fs::temp_directory_path() / "squint_calibrate_test_onedist.yaml";
  fs::remove(out);
  const CliResult r = RunSquint("calibrate " + seq.string() + " --only distance --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.all();
  EXPECT_NE(r.all().find("singular calibration: the true distances"), std::string::npos) << r.all();
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(seq);
}

TEST(CalibrateCli, SharedDataCalibrationIsReadBackAndOverlapWarned) {
  const fs::path data = SQUINT_SHARED_DATA_DIR;
  if (!fs::exists(data / "orient-1-00") || !fs::exists(data / "drive-3-00c")) GTEST_SKIP() << "no shared data";
  const fs::path out = fs::temp_directory_path() / "squint_calibrate_test_data.yaml";
  fs::remove(out);
  const std::string seqs = (data / "orient-1-00").string() + " " + (data / "drive-3-00c").string();
  CliResult r = RunSquint("calibrate " + seqs + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  ASSERT_TRUE(fs::exists(out));
  // The written options turn the heading filter on, with each cue's fitted sigma; not with
  // --no-heading-filter.
  const YAML::Node with = YAML::LoadAllFromFile(out.string()).at(0)["heading"];
  EXPECT_TRUE(with["filter"]["enabled"].as<bool>());
  const fs::path plain = fs::temp_directory_path() / "squint_calibrate_test_data_plain.yaml";
  r = RunSquint("calibrate " + seqs + " --no-heading-filter --out " + plain.string());
  ASSERT_EQ(r.code, 0) << r.all();
  const YAML::Node without = YAML::LoadAllFromFile(plain.string()).at(0)["heading"];
  EXPECT_FALSE(without["filter"]["enabled"].as<bool>());
  const double sigma = with["cues"]["phase"]["std_deg"].as<double>();
  EXPECT_EQ(without["cues"]["phase"]["std_deg"].as<double>(), sigma);
  EXPECT_NE(sigma, 8.0);  // the fitted sigma, not the default
  EXPECT_GE(sigma, 0.5);
  fs::remove(plain);
  r = RunSquint("perceive " + (data / "orient-1-01").string() + " --calib " + out.string() + " --out " +
                (fs::temp_directory_path() / "squint_calibrate_test.csv").string());
  EXPECT_EQ(r.code, 0) << r.all();
  const fs::path ev = fs::temp_directory_path() / "squint_calibrate_test_eval";
  fs::remove_all(ev);
  r = RunSquint("eval corridor " + (data / "orient-1-00").string() + " --calib " + out.string() + " --no-plots --out " +
                ev.string());
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.all().find("warning: sequence 'orient-1-00' was also used to fit"), std::string::npos) << r.all();
  EXPECT_TRUE(fs::exists(ev / "report.json"));
  fs::remove_all(ev);
  fs::remove(out);
}

}  // namespace
