// Calibration maths: least squares recovers planted parameters, trimming rejects planted
// outliers, and singular inputs are refused with squint::Error.
#include "squint/corridor/calibration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "squint/core/error.hpp"

namespace squint::corridor {
namespace {

TEST(FitLine, RecoversExactLine) {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(i * 0.5 - 3.0);
    y.push_back(-2.5 * x.back() + 7.0);
  }
  const LineFit f = FitLine(x, y, "test");
  EXPECT_NEAR(f.slope, -2.5, 1e-12);
  EXPECT_NEAR(f.intercept, 7.0, 1e-12);
  EXPECT_NEAR(f.residual_rms, 0.0, 1e-12);
  EXPECT_EQ(f.inliers, 20u);
}

TEST(FitLine, NoisyFitWithinStandardErrorAndRejectsOutliers) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<double> x, y;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    x.push_back(-20.0 + 40.0 * i / (n - 1));
    y.push_back(1.3 * x.back() - 2.0 + noise(rng));
  }
  // 10% gross outliers, all on one side, which would pull plain least squares.
  for (int i = 0; i < n; i += 10) y[static_cast<std::size_t>(i)] += 30.0;
  const LineFit f = FitLine(x, y, "test");
  // Standard error of the slope: σ / (sqrt(n) · σx) with σx ≈ 11.5 → ≈ 0.0023; intercept σ/sqrt(n) ≈ 0.025.
  EXPECT_NEAR(f.slope, 1.3, 5 * 0.0023);
  EXPECT_NEAR(f.intercept, -2.0, 5 * 0.026);
  EXPECT_NEAR(f.residual_rms, 0.5, 0.1);
  EXPECT_LE(f.inliers, static_cast<std::size_t>(n - n / 10 + 2));

  LineFitOptions plain;
  plain.trim_iterations = 0;
  const LineFit p = FitLine(x, y, "test", plain);
  EXPECT_GT(std::abs(p.intercept + 2.0), 2.0);  // the outliers do pull the plain fit
}

TEST(FitLine, RejectsConstantX) {
  std::vector<double> x(10, 4.0), y;
  for (int i = 0; i < 10; ++i) y.push_back(i);
  EXPECT_THROW(FitLine(x, y, "ttc"), Error);
  try {
    FitLine(x, y, "ttc");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ttc: singular"), std::string::npos) << e.what();
  }
}

TEST(FitLine, RejectsTooFewSamples) {
  std::vector<double> x{1, 2, 3}, y{1, 2, 3};
  EXPECT_THROW(FitLine(x, y, "few"), Error);
}

TEST(FitProportional, RecoversScaleAndRejectsZeros) {
  std::vector<double> x, y;
  for (int i = 1; i <= 10; ++i) {
    x.push_back(i);
    y.push_back(0.8 * i);
  }
  EXPECT_NEAR(FitProportional(x, y, "p").slope, 0.8, 1e-12);
  std::vector<double> zeros(10, 0.0);
  EXPECT_THROW(FitProportional(zeros, y, "p"), Error);
}

TEST(FitHeading, RecoversScaleBiasAndReliableRange) {
  // raw = (truth - bias) / scale with a measure that breaks down beyond ±12°.
  std::vector<HeadingSample> s;
  for (int rep = 0; rep < 5; ++rep)
    for (int h = -20; h <= 20; ++h) {
      double raw = (h - 1.5) / 0.9;
      if (std::abs(h) > 12 && rep < 2) raw = -raw * 1.5;  // wrong side, gross errors
      s.push_back({static_cast<double>(h), raw});
    }
  HeadingFitOptions free_scale;
  free_scale.fit_scale = true;
  const HeadingFit f = FitHeading(s, "entropy", free_scale);
  EXPECT_NEAR(f.scale, 0.9, 1e-9);
  EXPECT_NEAR(f.bias_deg, 1.5, 1e-9);
  EXPECT_NEAR(f.reliable_min_deg, -12.5, 1e-9);
  EXPECT_NEAR(f.reliable_max_deg, 12.5, 1e-9);
  EXPECT_GT(f.rmse_deg, 5.0);  // the outliers count in the reported error
}

TEST(FitHeading, CameraDegreesKeepScaleOneAndFitTheBiasPastGrossErrors) {
  // Readings in camera degrees, offset by a 2.5° mount yaw, with a third of them grossly wrong
  // (a cue peaking on the near wall): the bias is recovered and the scale stays 1, where a free
  // least-squares scale of truth on reading would shrink towards 0.
  std::vector<HeadingSample> s;
  for (int rep = 0; rep < 3; ++rep)
    for (int h = -20; h <= 20; ++h) {
      const double raw = (rep == 0 && h % 2 == 0) ? -25.0 + (h + 20) % 7 : h - 2.5;
      s.push_back({static_cast<double>(h), raw});
    }
  const HeadingFit f = FitHeading(s, "symmetry");
  EXPECT_EQ(f.scale, 1.0);
  EXPECT_NEAR(f.bias_deg, 2.5, 1e-9);
  EXPECT_NEAR(f.inlier_fraction, 102.0 / 123.0, 1e-9);
}

TEST(FitHeading, FreeScaleRejectsReadingsThatFallWithTheHeading) {
  std::vector<HeadingSample> s;
  for (int h = -20; h <= 20; ++h) s.push_back({static_cast<double>(h), -0.8 * h});
  HeadingFitOptions free_scale;
  free_scale.fit_scale = true;
  EXPECT_THROW(FitHeading(s, "bright", free_scale), Error);
}

TEST(FitHeading, RejectsAllHeadingsEqual) {
  std::vector<HeadingSample> s;
  for (int i = 0; i < 50; ++i) s.push_back({3.0, i * 0.1});
  EXPECT_THROW(FitHeading(s, "bright"), Error);
}

TEST(FitHeading, RejectsConstantRaw) {
  std::vector<HeadingSample> s;
  for (int h = -20; h <= 20; ++h) s.push_back({static_cast<double>(h), 0.0});
  EXPECT_THROW(FitHeading(s, "phase"), Error);
}

TEST(FitDistance, RecoversTtcScaleJeffreyAndEntropyConstants) {
  std::vector<DistanceSample> ttc, jd, ent;
  for (int i = 0; i < 150; ++i) {
    const double d = 15.0 - 0.1 * i;
    ttc.push_back({d, d / 1.25});
    jd.push_back({d, (9.0 - d) / 0.5});       // d = β2 − α2 J with β2 = 9, α2 = 0.5
    ent.push_back({d, -0.02 / d});            // d = α3 / ΔH with α3 = −0.02
  }
  DistanceFitOptions apply;
  apply.ttc_fit_scale = true;
  const DistanceFit t = FitTtcScale(ttc, "ttc", apply);
  EXPECT_NEAR(t.scale, 1.25, 1e-9);
  EXPECT_NEAR(t.checked_scale, 1.25, 1e-9);
  // By default the scale is only checked: the applied one stays 1.
  const DistanceFit checked = FitTtcScale(ttc, "ttc");
  EXPECT_NEAR(checked.checked_scale, 1.25, 1e-9);
  EXPECT_EQ(checked.scale, 1.0);
  EXPECT_NEAR(t.rmse_m, 0.0, 1e-9);
  const DistanceFit j = FitJeffrey(jd, "jeffrey");
  EXPECT_NEAR(j.alpha, 0.5, 1e-9);
  EXPECT_NEAR(j.beta, 9.0, 1e-9);
  const DistanceFit e = FitEntropyDistance(ent, "entropy");
  EXPECT_NEAR(e.alpha, -0.02, 1e-12);
  EXPECT_NEAR(e.rmse_m, 0.0, 1e-9);
}

TEST(FitDistance, RejectsOneDistanceOnly) {
  std::vector<DistanceSample> s;
  for (int i = 0; i < 40; ++i) s.push_back({4.0, 0.1 * i});
  EXPECT_THROW(FitTtcScale(s, "ttc"), Error);
  EXPECT_THROW(FitJeffrey(s, "jeffrey"), Error);
  EXPECT_THROW(FitEntropyDistance(s, "entropy"), Error);
}

TEST(FitDistanceSpread, RecoversGrowingSpread) {
  // |e| · sqrt(π/2) = 0.1 + 0.05 d exactly when |e| is set so.
  std::vector<double> est, err;
  for (int i = 0; i < 100; ++i) {
    const double d = 0.5 + 0.1 * i;
    est.push_back(d);
    err.push_back((i % 2 ? 1.0 : -1.0) * (0.1 + 0.05 * d) / std::sqrt(M_PI / 2.0));
  }
  const DistanceSpread s = FitDistanceSpread(est, err);
  EXPECT_NEAR(s.sigma0_m, 0.1, 1e-9);
  EXPECT_NEAR(s.sigma_slope, 0.05, 1e-9);
  EXPECT_NEAR(s.Sigma(4.0), 0.3, 1e-9);
}

}  // namespace
}  // namespace squint::corridor
