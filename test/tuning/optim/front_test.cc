// The front's pure parts (tuning/optim/front.h): the budgets of its points and the 2-D
// hypervolume its quality is measured with.
#include "tuning/optim/front.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::tuning {
namespace {

TEST(FrontTest, BudgetsRunFromNoLossToNoBudgetDensestNearNoLoss) {
  const int n = 5;
  const double span = 0.4;
  const CleanLapBudget first = FrontBudget(0, n, span), last = FrontBudget(n - 1, n, span);
  EXPECT_EQ(first.lap_s, 0.0);
  EXPECT_TRUE(first.interventions);
  EXPECT_FALSE(std::isfinite(last.lap_s));
  EXPECT_FALSE(last.interventions);
  EXPECT_DOUBLE_EQ(FrontBudget(1, n, span).lap_s, 0.025);
  EXPECT_DOUBLE_EQ(FrontBudget(2, n, span).lap_s, 0.1);
  EXPECT_DOUBLE_EQ(FrontBudget(3, n, span).lap_s, 0.225);
  for (int k = 1; k < n - 1; ++k) EXPECT_FALSE(FrontBudget(k, n, span).interventions);
  // A front of two is its ends.
  EXPECT_EQ(FrontBudget(0, 2, span).lap_s, 0.0);
  EXPECT_FALSE(std::isfinite(FrontBudget(1, 2, span).lap_s));
}

// The span L of the inner budgets: the unbudgeted end's loss, at least kFrontMinSpan, so an
// unbudgeted search that found nothing to buy with lap time (loss 0, as the built-in front's
// 120-evaluation search once did) leaves the inner points budgets to search, not four copies of "no
// loss".
TEST(FrontTest, SpanIsTheUnbudgetedLossButNeverBelowTheMinimum) {
  EXPECT_EQ(FrontSpan(0.0), kFrontMinSpan);
  EXPECT_EQ(FrontSpan(-0.001), kFrontMinSpan);
  EXPECT_EQ(FrontSpan(std::nan("")), kFrontMinSpan);
  EXPECT_EQ(FrontSpan(0.9), 0.9);
  EXPECT_GT(FrontBudget(1, 5, FrontSpan(0.0)).lap_s, 0.0);
}

// The ends start from the base point and get the whole budget (the built-in set's unbudgeted
// search found its trade only after ~210 evaluations); the warm-started inner points half.
TEST(FrontTest, TheEndsSearchWithTheWholeBudgetTheInnerPointsWithTwice) {
  EXPECT_EQ(FrontPointEvals(0, 5, 240), 240);
  EXPECT_EQ(FrontPointEvals(4, 5, 240), 240);
  for (int k = 1; k < 4; ++k) EXPECT_EQ(FrontPointEvals(k, 5, 240), 480);
  EXPECT_EQ(FrontPointEvals(1, 3, 3), 6);
  EXPECT_EQ(FrontPointEvals(1, 3, 1), 2);
  EXPECT_EQ(FrontPointEvals(1, 2, 7), 7);  // a front of two is its ends
}

TEST(FrontTest, HypervolumeIsTheAreaTheFrontDominatesUpToTheReference) {
  // Two non-dominated points and one dominated one; reference (1, 10).
  const double hv = Hypervolume2D({{0.0, 8.0}, {0.5, 4.0}, {0.6, 5.0}}, {1.0, 10.0});
  // [0, 0.5) x (8, 10]: 0.5 * 2 = 1.0 (at x in [0, 0.5) only the first point dominates),
  // [0.5, 1) x (4, 10]: 0.5 * 6 = 3.0.
  EXPECT_DOUBLE_EQ(hv, 4.0);
  // Order does not matter; a point beyond the reference adds nothing.
  EXPECT_DOUBLE_EQ(Hypervolume2D({{1.5, 0.0}, {0.5, 4.0}, {0.0, 8.0}}, {1.0, 10.0}), 4.0);
  EXPECT_DOUBLE_EQ(Hypervolume2D({}, {1.0, 10.0}), 0.0);
  // A better front dominates more.
  EXPECT_GT(Hypervolume2D({{0.0, 7.0}, {0.5, 4.0}}, {1.0, 10.0}), hv);
}

}  // namespace
}  // namespace scw::tuning
