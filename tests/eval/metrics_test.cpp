// Metrics on constructed samples with known answers: RMSE, coverage, bins, sign agreement.
#include "squint/eval/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace squint::eval {
namespace {

TEST(Metrics, SummarizeCountsCoverageAndRmse) {
  std::vector<Sample> s{{1.0, 2.0}, {2.0, 0.0}, {3.0, std::nullopt}, {4.0, 4.0}};
  const ErrorSummary e = Summarize(s);
  EXPECT_EQ(e.frames, 4u);
  EXPECT_EQ(e.estimated, 3u);
  EXPECT_DOUBLE_EQ(e.coverage, 0.75);
  EXPECT_NEAR(e.rmse, std::sqrt((1.0 + 4.0 + 0.0) / 3.0), 1e-12);
  EXPECT_NEAR(e.mean_error, (1.0 - 2.0) / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.max_abs_error, 2.0);
  const ErrorSummary r = SummarizeRange(s, 1.5, 3.5);
  EXPECT_EQ(r.frames, 2u);
  EXPECT_EQ(r.estimated, 1u);
  EXPECT_DOUBLE_EQ(r.rmse, 2.0);
}

TEST(Metrics, EmptyInputGivesZerosNotNan) {
  const ErrorSummary e = Summarize({});
  EXPECT_EQ(e.frames, 0u);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.coverage, 0.0);
  EXPECT_EQ(SignAgreement({}, 5.0).fraction, 0.0);
}

TEST(Metrics, BinsHoldMeanSigmaAndSign) {
  std::vector<Sample> s{{-1.2, -2.0}, {-1.4, 1.0}, {0.2, 0.0}, {0.0, 3.0}, {0.7, 2.0}};
  const std::vector<BinStats> b = BinByTruth(s, 1.0, -0.5);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_DOUBLE_EQ(b[0].lo, -1.5);
  EXPECT_EQ(b[0].frames, 2u);
  EXPECT_DOUBLE_EQ(b[0].mean_estimate, -0.5);
  EXPECT_DOUBLE_EQ(b[0].std_estimate, 1.5);
  EXPECT_DOUBLE_EQ(b[0].right_sign_fraction, 0.5);
  EXPECT_DOUBLE_EQ(b[1].lo, -0.5);
  EXPECT_EQ(b[1].frames, 2u);  // 0.2 and 0.0; 0.7 falls into [0.5, 1.5)
  EXPECT_EQ(b[2].frames, 1u);
  EXPECT_DOUBLE_EQ(b[2].right_sign_fraction, 1.0);
  // truth 0 has no sign; 0.2 → estimate 0 is not positive.
  EXPECT_EQ(b[1].signed_frames, 1u);
  EXPECT_DOUBLE_EQ(b[1].right_sign_fraction, 0.0);
}

TEST(Metrics, SignAgreementHonoursThreshold) {
  std::vector<Sample> s{{-10, -3}, {-6, 2}, {4, -1}, {7, 1}, {12, std::nullopt}};
  const SignSummary g = SignAgreement(s, 5.0);
  EXPECT_EQ(g.frames, 3u);
  EXPECT_EQ(g.right, 2u);
}

TEST(Metrics, HistogramAndBlocks) {
  std::vector<double> v{-1, 0.05, 0.15, 0.15, 2.0};
  const Histogram h = MakeHistogram(v, 0.0, 0.2, 2);
  EXPECT_EQ(h.counts[0], 2u);
  EXPECT_EQ(h.counts[1], 3u);
  EXPECT_EQ(h.underflow, 1u);
  EXPECT_EQ(h.overflow, 1u);
  const std::vector<bool> f{true, false, true, true, true};
  const std::vector<std::size_t> c = CountPerBlock(f, 2);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], 1u);
  EXPECT_EQ(c[1], 2u);
  EXPECT_EQ(c[2], 1u);
}

}  // namespace
}  // namespace squint::eval
