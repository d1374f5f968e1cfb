// Sequence format round trips and every kind of bad input named in SEQUENCE_FORMAT.md.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/io/camera_yaml.hpp"
#include "squint/io/csv.hpp"
#include "squint/io/frame_source.hpp"
#include "squint/io/sequence.hpp"

namespace squint::io {
namespace {
namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("squint-io-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                         "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& Path() const { return path_; }

 private:
  fs::path path_;
};

SequenceInfo SmallInfo() {
  SequenceInfo info;
  info.name = "round-trip";
  info.camera.width = 32;
  info.camera.height = 24;
  info.camera.fx = info.camera.fy = 35.25;
  info.camera.cx = 15.5;
  info.camera.cy = 11.5;
  info.camera.height_m = 0.69;
  info.camera.pitch_deg = -1.5;
  info.camera.distortion = {-0.1, 0.02, 0.001, 0.0, 0.0};
  info.frame_rate_hz = 30.0;
  return info;
}

cv::Mat Pattern(int seed) {
  cv::Mat m(24, 32, CV_8UC1);
  for (int v = 0; v < 24; ++v)
    for (int u = 0; u < 32; ++u) m.at<uchar>(v, u) = static_cast<uchar>((u * 7 + v * 13 + seed * 31) % 256);
  return m;
}

fs::path WriteSmallSequence(const fs::path& dir, bool with_labels) {
  SequenceWriter w(dir, SmallInfo());
  for (int i = 0; i < 3; ++i) {
    FrameRecord r;
    r.stamp = i / 30.0;
    r.odom = Pose2{0.1 * i, -0.01 * i, 0.002 * i};
    r.gt.heading_deg = 1.5 * i;
    r.gt.lateral_m = -0.25;
    r.gt.dist_end_m = 10.0 - 0.1 * i;
    w.Add(r, Pattern(i), with_labels ? (Pattern(i) > 128) : cv::Mat());
  }
  w.Finish();
  return dir;
}

TEST(Sequence, WriteReadRoundTrip) {
  TempDir t;
  const fs::path dir = WriteSmallSequence(t.Path() / "seq", true);
  const Sequence s = Sequence::Read(dir);
  ASSERT_EQ(s.Size(), 3u);
  EXPECT_EQ(s.Info().name, "round-trip");
  EXPECT_EQ(s.Camera().width, 32);
  EXPECT_NEAR(s.Camera().fx, 35.25, 1e-9);
  EXPECT_NEAR(s.Camera().pitch_deg, -1.5, 1e-9);
  ASSERT_EQ(s.Camera().distortion.size(), 5u);
  EXPECT_NEAR(s.Camera().distortion[0], -0.1, 1e-12);
  ASSERT_TRUE(s.Info().frame_rate_hz.has_value());
  EXPECT_TRUE(s.HasOdometry());
  EXPECT_TRUE(s.HasLabels());
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& r = s.Frames()[i];
    EXPECT_NEAR(r.stamp, i / 30.0, 1e-6);
    EXPECT_NEAR(r.odom->x, 0.1 * i, 1e-6);
    EXPECT_NEAR(r.odom->yaw, 0.002 * i, 1e-7);
    EXPECT_NEAR(*r.gt.heading_deg, 1.5 * i, 1e-4);
    EXPECT_NEAR(*r.gt.dist_end_m, 10.0 - 0.1 * i, 1e-5);
    EXPECT_EQ(cv::norm(s.LoadImage(i), Pattern(static_cast<int>(i)), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(s.LoadLabel(i), Pattern(static_cast<int>(i)) > 128, cv::NORM_INF), 0.0);
  }
}

TEST(Sequence, UnfinishedWriterLeavesNothing) {
  TempDir t;
  {
    SequenceWriter w(t.Path() / "seq", SmallInfo());
    w.Add(FrameRecord{}, Pattern(0));
  }
  EXPECT_FALSE(fs::exists(t.Path() / "seq"));
  EXPECT_TRUE(fs::is_empty(t.Path()));
}

// Expects Sequence::Read to throw squint::Error whose message contains `needle`.
void ExpectReadError(const fs::path& dir, const std::string& needle) {
  try {
    (void)Sequence::Read(dir);
    FAIL() << "no error for " << dir;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

void Rewrite(const fs::path& file, const std::string& from, const std::string& to) {
  std::ifstream in(file);
  std::string s((std::istreambuf_iterator<char>(in)), {});
  const auto pos = s.find(from);
  ASSERT_NE(pos, std::string::npos);
  s.replace(pos, from.size(), to);
  std::ofstream(file) << s;
}

TEST(Sequence, BadInputsGiveErrorsNamingTheFile) {
  TempDir t;
  const fs::path good = WriteSmallSequence(t.Path() / "good", false);
  auto copy = [&](const std::string& name) {
    fs::copy(good, t.Path() / name, fs::copy_options::recursive);
    return t.Path() / name;
  };
  ExpectReadError(t.Path() / "nowhere", "not a folder");

  fs::path d = copy("noyaml");
  fs::remove(d / "sequence.yaml");
  ExpectReadError(d, "sequence.yaml: missing");

  d = copy("format");
  Rewrite(d / "sequence.yaml", "squint-sequence/1", "squint-sequence/9");
  ExpectReadError(d, "squint-sequence/9");

  d = copy("nocolumn");
  Rewrite(d / "frames.csv", "stamp,", "time,");
  ExpectReadError(d, "missing required column 'stamp'");

  d = copy("truncated");
  Rewrite(d / "frames.csv", ",-0.25000,", ",");
  ExpectReadError(d, "line 2");

  d = copy("nonnumeric");
  Rewrite(d / "frames.csv", "0.100000,", "abc,");
  ExpectReadError(d, "'abc' is not a finite number");

  d = copy("nocamera");
  Rewrite(d / "sequence.yaml", "fx:", "fz:");
  ExpectReadError(d, "missing key 'fx'");

  d = copy("badimage");
  std::ofstream(d / "images/000001.png") << "not a png";
  const Sequence s = Sequence::Read(d);
  EXPECT_THROW((void)s.LoadImage(1), Error);
  fs::remove(d / "images/000002.png");
  try {
    (void)s.LoadImage(2);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("000002.png"), std::string::npos);
  }
  cv::imwrite((d / "images/000000.png").string(), cv::Mat(10, 10, CV_8UC1, cv::Scalar(3)));
  EXPECT_THROW((void)s.LoadImage(0), Error);
}

TEST(Csv, NumbersAndErrors) {
  TempDir t;
  std::ofstream(t.Path() / "a.csv") << "x,y\n1.5,\n2,abc\n";
  const CsvTable c = CsvTable::Read(t.Path() / "a.csv");
  EXPECT_EQ(c.Rows(), 2u);
  EXPECT_DOUBLE_EQ(*c.Number(0, 0), 1.5);
  EXPECT_FALSE(c.Number(0, 1).has_value());
  EXPECT_THROW((void)c.Number(1, 1), Error);
  EXPECT_THROW((void)c.Require("z"), Error);
  EXPECT_EQ(CsvNumber(-0.00001, 3), "0.000");
  EXPECT_EQ(CsvNumber(std::optional<double>{}), "");
}

TEST(AtomicFile, NothingAppearsUntilCommit) {
  TempDir t;
  const fs::path p = t.Path() / "out.csv";
  {
    AtomicFile f(p);
    f.Stream() << "half";
    EXPECT_FALSE(fs::exists(p));
  }
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(t.Path()));
  WriteFileAtomically(p, "whole\n");
  std::ifstream in(p);
  std::string s;
  std::getline(in, s);
  EXPECT_EQ(s, "whole");
}

TEST(CameraYaml, ReadsRosCameraInfo) {
  TempDir t;
  std::ofstream(t.Path() / "cam.yaml") << "image_width: 640\nimage_height: 480\ncamera_name: webcam\n"
                                          "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [500, 0, 319.5, 0, 501, 239.5, 0, 0, 1]\n"
                                          "distortion_model: plumb_bob\n"
                                          "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.2, 0.1, 0, 0, 0]\n"
                                          "mount_height_m: 0.4\nmount_pitch_deg: -5\n";
  const CameraModel c = LoadCameraYaml(t.Path() / "cam.yaml");
  EXPECT_EQ(c.width, 640);
  EXPECT_DOUBLE_EQ(c.fy, 501.0);
  EXPECT_DOUBLE_EQ(c.cx, 319.5);
  EXPECT_DOUBLE_EQ(c.height_m, 0.4);
  EXPECT_DOUBLE_EQ(c.pitch_deg, -5.0);
  ASSERT_EQ(c.distortion.size(), 5u);
  std::ofstream(t.Path() / "bad.yaml") << "camera_matrix:\n  data: [1, 2]\nimage_width: 4\nimage_height: 3\n";
  EXPECT_THROW((void)LoadCameraYaml(t.Path() / "bad.yaml"), Error);
  // A sequence.yaml works too.
  const fs::path seq = WriteSmallSequence(t.Path() / "seq", false);
  EXPECT_EQ(LoadCameraYaml(seq / "sequence.yaml").width, 32);
}

TEST(FrameSource, ImageFolderVideoAndSequence) {
  TempDir t;
  fs::create_directories(t.Path() / "imgs");
  for (int i = 0; i < 4; ++i)
    cv::imwrite((t.Path() / "imgs" / ("f" + std::to_string(i) + ".png")).string(), Pattern(i));
  auto src = OpenFrameSource(t.Path() / "imgs", {10.0});
  int n = 0;
  while (auto f = src->Next()) {
    EXPECT_NEAR(f->stamp, n / 10.0, 1e-12);
    EXPECT_EQ(f->image.cols, 32);
    ++n;
  }
  EXPECT_EQ(n, 4);

  const fs::path video = t.Path() / "v.avi";
  {
    cv::VideoWriter vw(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 15.0, cv::Size(32, 24), false);
    if (!vw.isOpened()) GTEST_SKIP() << "this OpenCV cannot write MJPG video";
    for (int i = 0; i < 5; ++i) vw.write(Pattern(i));
  }
  auto vs = OpenFrameSource(video);
  n = 0;
  while (auto f = vs->Next()) {
    EXPECT_NEAR(f->stamp, n / 15.0, 1e-9);
    EXPECT_EQ(f->image.channels(), 1);
    ++n;
  }
  EXPECT_EQ(n, 5);

  std::ofstream(t.Path() / "broken.avi") << "garbage";
  EXPECT_THROW((void)OpenFrameSource(t.Path() / "broken.avi"), Error);
  EXPECT_THROW((void)OpenFrameSource(t.Path() / "missing"), Error);
  const fs::path seq = WriteSmallSequence(t.Path() / "seq", false);
  auto ss = OpenFrameSource(seq);
  ASSERT_TRUE(ss->Camera().has_value());
  EXPECT_EQ(*ss->Count(), 3u);
  // A sequence folder that lost its sequence.yaml is named as such (not read as an image folder).
  fs::remove(seq / "sequence.yaml");
  try {
    (void)OpenFrameSource(seq);
    ADD_FAILURE() << "a sequence without sequence.yaml was opened";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sequence.yaml: missing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace squint::io

namespace squint::io {
namespace {

TEST(Sequence, ReadsEverySharedDataSequence) {
  const std::filesystem::path data = SQUINT_SHARED_DATA_DIR;
  if (!std::filesystem::is_directory(data)) GTEST_SKIP() << "../shared/data is absent";
  int sequences = 0;
  for (const auto& e : std::filesystem::directory_iterator(data)) {
    if (!std::filesystem::exists(e.path() / "sequence.yaml")) continue;
    const Sequence s = Sequence::Read(e.path());
    EXPECT_GT(s.Size(), 10u) << e.path();
    EXPECT_TRUE(s.HasOdometry()) << e.path();
    const cv::Mat first = s.LoadImage(0);
    EXPECT_EQ(first.cols, s.Camera().width);
    if (s.HasLabels()) {
      EXPECT_EQ(s.LoadLabel(0).size(), first.size());
    }
    ++sequences;
  }
  EXPECT_GT(sequences, 0);
}

}  // namespace
}  // namespace squint::io
