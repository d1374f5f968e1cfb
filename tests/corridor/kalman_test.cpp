// The heading / distance Kalman filter: converges on a constructed constant-velocity approach,
// follows odometry rotations, and gates gross outliers.
#include "squint/corridor/kalman.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "squint/core/angles.hpp"

namespace squint::corridor {
namespace {

TEST(CorridorKalman, ConvergesOnConstantVelocityApproach) {
  // The robot drives straight at 0.1 m per frame from 15 m; the measurement is the truth plus
  // noise of σ = 1 m and starts 4 m off. Odometry is exact.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  CorridorKalman kf;
  double truth = 15.0;
  kf.Predict(std::nullopt);
  kf.UpdateDistance(truth + 4.0, 1.0);
  double last_err = 0.0;
  for (int i = 1; i < 140; ++i) {
    truth -= 0.1;
    kf.Predict(Pose2{0.1, 0.0, 0.0});
    kf.UpdateDistance(truth + noise(rng), 1.0);
    last_err = *kf.DistanceM() - truth;
  }
  // ~140 measurements of σ = 1 m with near-exact odometry: σ of the estimate well below 0.3 m.
  EXPECT_LT(std::abs(last_err), 0.45);
  EXPECT_LT(kf.DistanceStdM(), 0.3);
  EXPECT_GT(kf.DistanceStdM(), 0.0);
}

TEST(CorridorKalman, OdometryRotatesHeadingAndProjectsTravel) {
  CorridorKalman kf;
  kf.UpdateHeading(0.0, 0.5);
  kf.UpdateDistance(10.0, 0.1);
  kf.Predict(Pose2{0.0, 0.0, DegToRad(30.0)});  // turn in place 30° left
  EXPECT_NEAR(*kf.HeadingDeg(), 30.0, 1e-9);
  EXPECT_NEAR(*kf.DistanceM(), 10.0, 1e-9);
  kf.Predict(Pose2{1.0, 0.0, 0.0});  // 1 m forward at 30°: 0.866 m along the corridor
  EXPECT_NEAR(*kf.DistanceM(), 10.0 - std::cos(DegToRad(30.0)), 1e-9);
}

TEST(CorridorKalman, GatesOutliersAndReinitialisesAfterPersistentDisagreement) {
  CorridorKalmanOptions o;
  o.reinit_after_rejections = 3;
  CorridorKalman kf(o);
  kf.UpdateHeading(2.0, 1.0);
  for (int i = 0; i < 5; ++i) {
    kf.Predict(Pose2{0.1, 0.0, 0.0});
    kf.UpdateHeading(2.0, 1.0);
  }
  kf.Predict(Pose2{0.1, 0.0, 0.0});
  EXPECT_FALSE(kf.UpdateHeading(40.0, 1.0));  // gross outlier rejected
  EXPECT_NEAR(*kf.HeadingDeg(), 2.0, 0.5);
  EXPECT_FALSE(kf.UpdateHeading(40.0, 1.0));
  EXPECT_FALSE(kf.UpdateHeading(40.0, 1.0));
  EXPECT_TRUE(kf.UpdateHeading(40.0, 1.0));   // after 3 rejections: a new corridor
  EXPECT_NEAR(*kf.HeadingDeg(), 40.0, 1e-9);
}

TEST(CorridorKalman, NoEstimateBeforeFirstMeasurement) {
  CorridorKalman kf;
  kf.Predict(Pose2{0.1, 0.0, 0.0});
  EXPECT_FALSE(kf.HeadingDeg().has_value());
  EXPECT_FALSE(kf.DistanceM().has_value());
  EXPECT_FALSE(kf.UpdateDistance(std::nan(""), 1.0));
  EXPECT_FALSE(kf.DistanceM().has_value());
}

TEST(CorridorKalman, SetHeadingStartsFromThePriorAndWeighsTheNextMeasurement) {
  CorridorKalman kf;
  kf.SetHeading(5.0, 2.0);
  ASSERT_TRUE(kf.HeadingDeg().has_value());
  EXPECT_NEAR(*kf.HeadingDeg(), 5.0, 1e-12);
  EXPECT_NEAR(kf.HeadingStdDeg(), 2.0, 1e-12);
  // Equal variances: the measurement moves the state halfway, not onto itself.
  EXPECT_TRUE(kf.UpdateHeading(9.0, 2.0));
  EXPECT_NEAR(*kf.HeadingDeg(), 7.0, 1e-9);
  EXPECT_NEAR(kf.HeadingStdDeg(), std::sqrt(2.0), 1e-9);
  // A measurement far outside the prior is gated out instead of restarting the state.
  CorridorKalman gated;
  gated.SetHeading(0.0, 1.0);
  EXPECT_FALSE(gated.UpdateHeading(12.0, 1.0));
  EXPECT_NEAR(*gated.HeadingDeg(), 0.0, 1e-12);
  // No distance came with it; a non-finite or non-positive prior is ignored.
  EXPECT_FALSE(kf.DistanceM().has_value());
  CorridorKalman none;
  none.SetHeading(std::nan(""), 1.0);
  none.SetHeading(3.0, 0.0);
  EXPECT_FALSE(none.HeadingDeg().has_value());
}

TEST(CorridorKalmanOptions, ValidateRejectsBadValues) {
  CorridorKalmanOptions o;
  EXPECT_TRUE(o.Validate().empty());
  o.gate_chi2 = 0.0;
  EXPECT_FALSE(o.Validate().empty());
}

}  // namespace
}  // namespace squint::corridor
