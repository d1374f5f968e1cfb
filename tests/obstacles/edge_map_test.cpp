// Tests of the horizontal Gaussian-derivative edge map and its hysteresis thresholds.
#include "squint/obstacles/edge_map.hpp"

#include <gtest/gtest.h>

namespace squint::obstacles {
namespace {

// A vertical step of `step` grey levels at column 32 in rows [v0, v1).
cv::Mat Step(int step, int v0 = 0, int v1 = 48) {
  cv::Mat img(48, 64, CV_8U, cv::Scalar(100));
  for (int v = v0; v < v1; ++v)
    for (int u = 32; u < 64; ++u) img.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(100 + step);
  return img;
}

TEST(EdgeMapTest, KernelIsAntisymmetricWithUnitLobes) {
  EdgeMapper m;
  const cv::Mat& k = m.Kernel();
  const int n = k.cols;
  double pos = 0, neg = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_FLOAT_EQ(k.at<float>(0, i), -k.at<float>(0, n - 1 - i));
    (k.at<float>(0, i) > 0 ? pos : neg) += k.at<float>(0, i);
  }
  EXPECT_NEAR(pos, 1.0, 1e-6);
  EXPECT_NEAR(neg, -1.0, 1e-6);
}

TEST(EdgeMapTest, StepResponseEqualsStepHeight) {
  EdgeMapper m;
  m.Compute(Step(80));
  // The step lies between columns 31 and 32; both see about the whole step (a sampled Gaussian
  // derivative puts a little weight on the pixel at its centre, hence the tolerance of a few %).
  const float g = std::max(m.Gradient().at<float>(10, 31), m.Gradient().at<float>(10, 32));
  EXPECT_NEAR(g, 80.0, 80.0 * 0.25);
  EXPECT_NEAR(m.Gradient().at<float>(10, 10), 0.0, 1e-4);
}

TEST(EdgeMapTest, StrongStepIsAnEdgeWeakIsNot) {
  EdgeMapper m;  // low 40, high 50
  const cv::Mat& strong = m.Compute(Step(80));
  EXPECT_EQ(strong.at<std::uint8_t>(20, 31) | strong.at<std::uint8_t>(20, 32), 255);
  EXPECT_EQ(strong.at<std::uint8_t>(20, 5), 0);
  EXPECT_EQ(strong.at<std::uint8_t>(20, 60), 0);
  const cv::Mat& weak = m.Compute(Step(30));
  EXPECT_EQ(cv::countNonZero(weak), 0);
}

TEST(EdgeMapTest, HysteresisKeepsWeakPixelsConnectedToStrongOnes) {
  EdgeMapOptions o;
  o.low_threshold = 40;
  o.high_threshold = 60;
  EdgeMapper m(o);
  // Upper half: a step of 80 (strong); lower half: 50 (weak), the same vertical edge.
  cv::Mat img = Step(50);
  for (int v = 0; v < 24; ++v)
    for (int u = 32; u < 64; ++u) img.at<std::uint8_t>(v, u) = 180;
  const cv::Mat& e = m.Compute(img);
  EXPECT_EQ(e.at<std::uint8_t>(40, 31) | e.at<std::uint8_t>(40, 32), 255) << "weak, connected: kept";
  // The same weak step alone has no strong seed.
  const cv::Mat& alone = m.Compute(Step(50));
  EXPECT_EQ(cv::countNonZero(alone), 0);
}

TEST(EdgeMapTest, HorizontalEdgesAreIgnored) {
  cv::Mat img(48, 64, CV_8U, cv::Scalar(100));
  img.rowRange(24, 48).setTo(220);
  EdgeMapper m;
  EXPECT_EQ(cv::countNonZero(m.Compute(img)), 0);
}

TEST(EdgeMapTest, BaseEdgesFindHorizontalEdgesOnly) {
  // A horizontal step (rows 24+ brighter): a base edge along rows 23/24, no vertical edge.
  cv::Mat img(48, 64, CV_8U, cv::Scalar(100));
  img.rowRange(24, 48).setTo(180);
  EdgeMapper m;
  EXPECT_EQ(cv::countNonZero(m.Compute(img)), 0);
  const cv::Mat& base = m.BaseEdges();
  ASSERT_EQ(base.size(), img.size());
  for (int u = 0; u < 64; ++u) EXPECT_EQ(base.at<std::uint8_t>(23, u) | base.at<std::uint8_t>(24, u), 255) << u;
  EXPECT_EQ(cv::countNonZero(base.rowRange(0, 21)), 0);
  EXPECT_EQ(cv::countNonZero(base.rowRange(27, 48)), 0);
  // A vertical step gives no base edge.
  m.Compute(Step(80));
  EXPECT_EQ(cv::countNonZero(m.BaseEdges()), 0);
  // Off: no base-edge map at all.
  EdgeMapOptions o;
  o.base_edges = false;
  EdgeMapper off(o);
  off.Compute(img);
  EXPECT_TRUE(off.BaseEdges().empty());
}

TEST(EdgeMapTest, InvalidOptionsAreNamed) {
  EdgeMapOptions o;
  o.high_threshold = 10;
  EXPECT_NE(o.Validate().find("high_threshold"), std::string::npos);
  o = {};
  o.sigma_px = 0;
  EXPECT_NE(o.Validate().find("sigma_px"), std::string::npos);
  EXPECT_TRUE(EdgeMapOptions{}.Validate().empty());
}

}  // namespace
}  // namespace squint::obstacles
