// ROC/AUC on constructed scores: perfect, reversed, tied, and a hand-computed case.
#include "squint/eval/roc.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace squint::eval {
namespace {

TEST(Roc, KnownAreas) {
  const std::vector<ScoredLabel> perfect = {{0.1, false}, {0.2, false}, {0.8, true}, {0.9, true}};
  EXPECT_DOUBLE_EQ(ComputeRoc(perfect).auc, 1.0);
  const std::vector<ScoredLabel> reversed = {{0.9, false}, {0.8, false}, {0.2, true}, {0.1, true}};
  EXPECT_DOUBLE_EQ(ComputeRoc(reversed).auc, 0.0);
  const std::vector<ScoredLabel> tied = {{0.5, false}, {0.5, true}, {0.5, false}, {0.5, true}};
  EXPECT_DOUBLE_EQ(ComputeRoc(tied).auc, 0.5);
  // Positives 0.9, 0.4; negatives 0.6, 0.1: pairs ordered right = 3 of 4.
  const std::vector<ScoredLabel> mixed = {{0.9, true}, {0.4, true}, {0.6, false}, {0.1, false}};
  EXPECT_DOUBLE_EQ(ComputeRoc(mixed).auc, 0.75);
  // +infinity scores (above the horizon) rank first.
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<ScoredLabel> with_inf = {{inf, true}, {inf, false}, {0.3, true}, {0.1, false}};
  // Pairs (positive, negative): (inf, inf) tie 0.5, (inf, 0.1) 1, (0.3, inf) 0, (0.3, 0.1) 1.
  EXPECT_DOUBLE_EQ(ComputeRoc(with_inf).auc, 2.5 / 4.0);
}

TEST(Roc, CurveIsMonotoneFromOriginToOne) {
  const std::vector<ScoredLabel> s = {{0.9, true}, {0.4, true}, {0.6, false}, {0.1, false}, {0.4, false}};
  const Roc r = ComputeRoc(s);
  ASSERT_GE(r.points.size(), 2u);
  EXPECT_EQ(r.points.front().fall_out, 0.0);
  EXPECT_EQ(r.points.front().recall, 0.0);
  EXPECT_EQ(r.points.back().fall_out, 1.0);
  EXPECT_EQ(r.points.back().recall, 1.0);
  for (std::size_t i = 1; i < r.points.size(); ++i) {
    EXPECT_GE(r.points[i].fall_out, r.points[i - 1].fall_out);
    EXPECT_GE(r.points[i].recall, r.points[i - 1].recall);
    // Each point's threshold reproduces its rates.
    const Confusion c = ConfusionAt(s, r.points[i].threshold);
    EXPECT_DOUBLE_EQ(c.FallOut(), r.points[i].fall_out);
    EXPECT_DOUBLE_EQ(c.Recall(), r.points[i].recall);
  }
}

TEST(Roc, OneClassIsUndefined) {
  const std::vector<ScoredLabel> s = {{0.1, true}, {0.2, true}};
  EXPECT_FALSE(ComputeRoc(s).Defined());
  EXPECT_EQ(ComputeRoc(s).auc, 0.0);
  EXPECT_FALSE(ComputeRoc({}).Defined());
}

}  // namespace
}  // namespace squint::eval
