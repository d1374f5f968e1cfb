// Robust F: correspondences of a known two-view geometry plus gross outliers.
#include "squint/obstacles/fundamental.hpp"

#include <gtest/gtest.h>

#include <random>

namespace squint::obstacles {
namespace {

TEST(Fundamental, SeparatesOutliersAndSatisfiesTheEpipolarConstraint) {
  // Camera K, second camera translated (0.1, 0.02, 0.3) and rotated 2° about y.
  const double f = 200.0, cx = 128.0, cy = 96.0;
  const double a = 2.0 * M_PI / 180.0;
  const cv::Matx33d R(std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a));
  const cv::Vec3d t(0.1, 0.02, 0.3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> X(-2, 2), Y(-1, 1), Z(3, 8), U(0, 255), V(0, 191);
  std::vector<cv::Point2f> p1, p2;
  std::vector<bool> truth;
  for (int i = 0; i < 150; ++i) {
    const cv::Vec3d P(X(rng), Y(rng), Z(rng));
    const cv::Vec3d Q = R * P + t;
    p1.emplace_back(static_cast<float>(f * P[0] / P[2] + cx), static_cast<float>(f * P[1] / P[2] + cy));
    p2.emplace_back(static_cast<float>(f * Q[0] / Q[2] + cx), static_cast<float>(f * Q[1] / Q[2] + cy));
    truth.push_back(true);
  }
  for (int i = 0; i < 40; ++i) {  // gross outliers
    p1.emplace_back(static_cast<float>(U(rng)), static_cast<float>(V(rng)));
    p2.emplace_back(static_cast<float>(U(rng)), static_cast<float>(V(rng)));
    truth.push_back(false);
  }
  FundamentalOptions opt;
  const auto r = EstimateFundamental(p1, p2, opt);
  ASSERT_TRUE(r.has_value());
  int wrong = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i]) {
      EXPECT_TRUE(r->inlier[i]) << i;
      EXPECT_LT(EpipolarDistance(r->F, p1[i], p2[i]), opt.inlier_threshold_px);
    } else if (r->inlier[i]) {
      ++wrong;  // a random pair can fall on its epipolar line by chance
    }
  }
  EXPECT_LE(wrong, 3);
  EXPECT_GE(r->refinements, 1);
  // Determinism.
  const auto again = EstimateFundamental(p1, p2, opt);
  EXPECT_EQ(again->inlier, r->inlier);
}

TEST(Fundamental, TooFewPointsGiveNoEstimate) {
  std::vector<cv::Point2f> p(5, cv::Point2f(1, 1));
  EXPECT_FALSE(EstimateFundamental(p, p, FundamentalOptions{}).has_value());
  EXPECT_FALSE(EstimateFundamental({}, {}, FundamentalOptions{}).has_value());
}

}  // namespace
}  // namespace squint::obstacles
