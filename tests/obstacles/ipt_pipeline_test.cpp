// The whole pipeline on a rendered pair (textured floor + a box front 2 m ahead, 31 mm step), and
// every degenerate pair: a status with a reason, never a throw.
#include "squint/obstacles/ipt_pipeline.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

#include "obstacle_camera.hpp"

namespace squint::obstacles {
namespace {

cv::Mat Texture(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> v(0, 255);
  cv::Mat small(64, 64, CV_8U);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 64; ++c) small.at<unsigned char>(r, c) = static_cast<unsigned char>(v(rng));
  cv::Mat t;
  cv::resize(small, t, cv::Size(512, 512), 0, 0, cv::INTER_CUBIC);
  return t;
}

constexpr double kBoxX = 2.0, kBoxHalfWidth = 0.4, kBoxHeight = 0.35;

// Renders the floor (texture in world coordinates, 5 mm texels, bilinear) and the front face of a box
// at x = kBoxX. `box_mask` (optional) marks the box pixels.
cv::Mat Render(const CameraModel& cam, const Pose2& pose, const cv::Mat& floor_tex, const cv::Mat& box_tex,
               cv::Mat* box_mask = nullptr) {
  cv::Mat img(cam.height, cam.width, CV_8U, cv::Scalar(90));
  if (box_mask) *box_mask = cv::Mat::zeros(cam.height, cam.width, CV_8U);
  auto sample = [](const cv::Mat& t, double x, double y) {
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int r, int c) { return static_cast<double>(t.at<unsigned char>(r & 511, c & 511)); };
    return (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) + fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
  };
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
      const Eigen::Vector2d dir = Eigen::Rotation2Dd(pose.yaw) * d.head<2>();
      const Eigen::Vector3d o(pose.x, pose.y, cam.height_m), dw(dir.x(), dir.y(), d.z());
      double best = 1e9, value = 90;
      if (dw.x() > 1e-9) {
        const double t = (kBoxX - o.x()) / dw.x();
        const Eigen::Vector3d p = o + t * dw;
        if (t > 0 && std::abs(p.y()) < kBoxHalfWidth && p.z() > 0 && p.z() < kBoxHeight) {
          best = t;
          value = sample(box_tex, (p.y() + kBoxHalfWidth) / 0.004, p.z() / 0.004);
          if (box_mask) box_mask->at<unsigned char>(v, u) = 255;
        }
      }
      if (dw.z() < -1e-9) {
        const double t = o.z() / -dw.z();
        if (t < best) {
          const Eigen::Vector3d p = o + t * dw;
          value = sample(floor_tex, p.x() / 0.005, p.y() / 0.005);
        }
      }
      img.at<unsigned char>(v, u) = static_cast<unsigned char>(std::clamp(value, 0.0, 255.0));
    }
  return img;
}

struct Scene {
  CameraModel cam = testing::SimObstacleCamera();
  Pose2 a{0.0, 0.0, 0.0}, b{0.031, 0.0, 0.0};
  cv::Mat ia, ib, box_b;
  Scene() {
    const cv::Mat ft = Texture(1), bt = Texture(2);
    ia = Render(cam, a, ft, bt);
    ib = Render(cam, b, ft, bt, &box_b);
  }
};

const Scene& TheScene() {
  static const Scene scene;
  return scene;
}

class PipelineByDetector : public ::testing::TestWithParam<Detector> {};

TEST_P(PipelineByDetector, FloorFeaturesHaveSmallDAndBoxFeaturesLargeD) {
  const Scene& s = TheScene();
  IptOptions opt;
  opt.features.detector = GetParam();
  // ORB keypoints sit on the integer pixel grid of a pyramid level (up to 0.5 px off, i.e. several
  // cm on the floor 2 m ahead): refine them to sub-pixel accuracy first.
  opt.features.refine_subpixel = GetParam() == Detector::kOrb;
  IptPipeline pipeline(s.cam, opt);
  const PairResult r = pipeline.Process(s.ia, s.ib, s.a, s.b);
  ASSERT_TRUE(r.Ok()) << r.reason;
  std::vector<double> floor_d;
  int box_features = 0, box_high = 0;
  for (const auto& f : r.measured) {
    ASSERT_TRUE(f.zone >= 0 && f.zone <= 3);
    if (!f.discrepancy_m) continue;
    // Margins of 2 px from the box outline: the label there is ambiguous.
    cv::Mat near;
    const int u = static_cast<int>(std::lround(f.pixel.x())), v = static_cast<int>(std::lround(f.pixel.y()));
    const cv::Rect win = cv::Rect(u - 2, v - 2, 5, 5) & cv::Rect(0, 0, s.cam.width, s.cam.height);
    const double box_share = cv::mean(s.box_b(win))[0] / 255.0;
    if (box_share == 0.0) floor_d.push_back(*f.discrepancy_m);
    if (box_share == 1.0) {
      // The box point's height from its row; D = 0.031 z / (h − z) (see ipt_geometry_test).
      ++box_features;
      const Eigen::Vector3d ray = s.cam.PixelRayRobot(f.pixel);
      const double z = s.cam.height_m + (kBoxX - s.b.x) / ray.x() * ray.z();
      const double expected = 0.031 * z / (s.cam.height_m - z);
      if (z > 0.1 && std::abs(*f.discrepancy_m - expected) < 0.5 * expected) ++box_high;
    }
  }
  ASSERT_GE(floor_d.size(), 20u);
  std::sort(floor_d.begin(), floor_d.end());
  // Floor points: D is zero up to tracking noise; a 0.1 px error 2 m ahead moves the floor point
  // by about 2²/(0.43·200)·0.1 ≈ 5 mm.
  EXPECT_LT(floor_d[floor_d.size() / 2], 0.005);
  ASSERT_GE(box_features, 5);
  // Most box features (z > 0.1) show the analytic D within ±50 %.
  EXPECT_GE(box_high, box_features / 2);
  // The hand-over holds exactly the classified features.
  std::size_t classified = 0;
  for (const auto& f : r.measured) classified += f.cls.has_value() ? 1 : 0;
  EXPECT_EQ(classified, r.features.size());
  // The classified discrepancy is the mirror-aware one (never above eq. 4's D, equal to it for
  // floor points moving against the camera); with mirror_aware off it is D itself.
  opt.mirror_aware = false;
  const PairResult plain = IptPipeline(s.cam, opt).Process(s.ia, s.ib, s.a, s.b);
  ASSERT_EQ(plain.measured.size(), r.measured.size());
  for (std::size_t i = 0; i < r.measured.size(); ++i) {
    const auto& f = r.measured[i];
    ASSERT_EQ(f.discrepancy_m.has_value(), f.plain_discrepancy_m.has_value());
    if (!f.discrepancy_m) continue;
    EXPECT_LE(*f.discrepancy_m, *f.plain_discrepancy_m + 1e-12);
    if (*f.signed_discrepancy_m >= 0.0) {
      EXPECT_NEAR(*f.discrepancy_m, *f.plain_discrepancy_m, 1e-12);
    }
    ASSERT_TRUE(plain.measured[i].discrepancy_m.has_value());
    EXPECT_EQ(*plain.measured[i].discrepancy_m, *f.plain_discrepancy_m);
  }
}

// Streaming reuses the earlier frame's detection when it equals the last later frame; the results must
// be exactly those of a fresh pipeline (nothing of an earlier pair may leak into the next), also when the caller overwrites one buffer with a new frame
// (same data pointer, different content: the reuse must not be keyed on the pointer).
void ExpectSameResult(const PairResult& x, const PairResult& y) {
  ASSERT_EQ(x.status, y.status);
  ASSERT_EQ(x.matches, y.matches);
  ASSERT_EQ(x.measured.size(), y.measured.size());
  for (std::size_t i = 0; i < x.measured.size(); ++i) {
    EXPECT_EQ(x.measured[i].pixel, y.measured[i].pixel);
    EXPECT_EQ(x.measured[i].previous_pixel, y.measured[i].previous_pixel);
    EXPECT_EQ(x.measured[i].cls, y.measured[i].cls);
  }
}

TEST_P(PipelineByDetector, StreamingGivesTheSameResultAsIsolatedPairs) {
  const Scene& s = TheScene();
  IptOptions opt;
  opt.features.detector = GetParam();
  IptPipeline stream(s.cam, opt);
  ASSERT_TRUE(stream.Process(s.ia, s.ib, s.a, s.b).Ok());
  {  // No reuse (a blank frame in between), but the matcher buffers hold an earlier pair's rows.
    IptPipeline used(s.cam, opt);
    const cv::Mat blank(s.cam.height, s.cam.width, CV_8U, cv::Scalar(128));
    used.Process(s.ia, s.ib, s.a, s.b);
    used.Process(blank, blank, s.a, s.b);
    ExpectSameResult(used.Process(s.ib, s.ia, s.b, s.a), IptPipeline(s.cam, opt).Process(s.ib, s.ia, s.b, s.a));
  }
  const PairResult back = stream.Process(s.ib, s.ia, s.b, s.a);  // earlier frame = last later frame
  ExpectSameResult(back, IptPipeline(s.cam, opt).Process(s.ib, s.ia, s.b, s.a));
  ASSERT_TRUE(back.Ok());
  // One buffer reused for the frames: after the pair (ib, buffer = ia), the buffer is overwritten
  // with ib and becomes the earlier frame of (buffer = ib, ia).
  cv::Mat buffer = s.ia.clone();
  const unsigned char* data = buffer.data;
  ASSERT_TRUE(stream.Process(s.ib, buffer, s.b, s.a).Ok());
  s.ib.copyTo(buffer);
  ASSERT_EQ(buffer.data, data);
  ExpectSameResult(stream.Process(buffer, s.ia, s.b, s.a), back);
}

INSTANTIATE_TEST_SUITE_P(Detectors, PipelineByDetector,
                         ::testing::Values(Detector::kSift, Detector::kOrb, Detector::kAkaze, Detector::kKlt),
                         [](const auto& info) { return DetectorName(info.param); });

TEST(PipelineDegenerate, EveryDegeneratePairGivesAStatusAndNoFeatures) {
  const Scene& s = TheScene();
  IptPipeline pipeline(s.cam, IptOptions{});
  auto expect = [&](PairResult r, PairStatus status) {
    EXPECT_EQ(r.status, status) << PairStatusName(r.status) << ": " << r.reason;
    EXPECT_FALSE(r.reason.empty());
    EXPECT_TRUE(r.features.empty());
    EXPECT_TRUE(r.measured.empty());
  };
  expect(pipeline.Process(s.ia, s.ib, std::nullopt, s.b), PairStatus::kMissingOdometry);
  expect(pipeline.Process(s.ia, s.ib, s.a, std::nullopt), PairStatus::kMissingOdometry);
  expect(pipeline.Process(s.ia, s.ia, s.a, s.a), PairStatus::kNoMotion);
  expect(pipeline.Process(s.ia, s.ib, s.a, Pose2{0.0, 0.0, 0.2}), PairStatus::kPureRotation);
  const cv::Mat blank(s.cam.height, s.cam.width, CV_8U, cv::Scalar(128));
  expect(pipeline.Process(blank, blank, s.a, s.b), PairStatus::kTooFewFeatures);
  expect(pipeline.Process(cv::Mat(), s.ib, s.a, s.b), PairStatus::kBadImage);
  expect(pipeline.Process(cv::Mat(10, 10, CV_8U, cv::Scalar(0)), s.ib, s.a, s.b), PairStatus::kBadImage);
  // The pipeline still works after the degenerate pairs.
  EXPECT_TRUE(pipeline.Process(s.ia, s.ib, s.a, s.b).Ok());
}

TEST(PipelineDegenerate, InvalidOptionsOrCameraThrowWithAReason) {
  IptOptions opt;
  opt.features.ratio = 1.5;
  try {
    IptPipeline p(testing::SimObstacleCamera(), opt);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("ratio"), std::string::npos) << e.what();
  }
  CameraModel bad = testing::SimObstacleCamera();
  bad.fx = 0.0;
  EXPECT_THROW(IptPipeline(bad, IptOptions{}), std::exception);
}

TEST(Pipeline, SameInputSameOutput) {
  const Scene& s = TheScene();
  IptPipeline p1(s.cam, IptOptions{}), p2(s.cam, IptOptions{});
  const PairResult a = p1.Process(s.ia, s.ib, s.a, s.b), b = p2.Process(s.ia, s.ib, s.a, s.b);
  ASSERT_EQ(a.features.size(), b.features.size());
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    EXPECT_EQ(a.features[i].pixel, b.features[i].pixel);
    EXPECT_EQ(a.features[i].cls, b.features[i].cls);
  }
}

}  // namespace
}  // namespace squint::obstacles
