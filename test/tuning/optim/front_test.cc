// The front's pure parts (tuning/optim/front.h): the budgets of its points, the rule that keeps
// the exported front monotone, and the 2-D hypervolume its quality is measured with.
#include "tuning/optim/front.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

// A point's exported report: its set, training clean-lap loss, extra activations, stability and
// own knife edges (-1: not checked).
TuneReport Exported(std::vector<double> u, double loss, int extra, double stability, int edges) {
  TuneReport r;
  r.exported_u = std::move(u);
  r.tuned_value.lap_loss = loss;
  r.tuned_value.extra_activations = extra;
  r.tuned_value.stability = stability;
  r.neighbourhood_done = edges >= 0;
  for (int i = 0; i < edges; ++i) r.neighbourhood.edges.emplace_back();
  return r;
}

// The --robust front on the built-in set ended point 4 (no budget) at 1184.5 with 17 knife edges
// beside point 3's 1161.5 with 1: the looser point takes the tighter one's set.
TEST(FrontTest, ALooserPointTakesItsTighterNeighboursSetOnlyWhenThatDominatesIt) {
  const CleanLapBudget none = FrontBudget(4, 5, 0.4), quarter = FrontBudget(3, 5, 0.4);
  const TuneReport point3 = Exported({0.2, 0.4}, -0.079, 3, 1161.5, 1);
  EXPECT_TRUE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1184.5, 17), none));
  // Lower in one, equal in the other.
  EXPECT_TRUE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1161.5, 2), none));
  EXPECT_TRUE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1170.0, 1), none));
  // Not when the looser set is better in either, or equal in both, or the same set.
  EXPECT_FALSE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1150.0, 17), none));
  EXPECT_FALSE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1184.5, 0), none));
  EXPECT_FALSE(TighterSetDominates(point3, Exported({0.3, 0.4}, -0.05, 0, 1161.5, 1), none));
  EXPECT_FALSE(TighterSetDominates(point3, Exported({0.2, 0.4}, -0.079, 3, 1184.5, 17), none));
  // Without a knife-edge check on either side the stability cost alone decides.
  EXPECT_TRUE(TighterSetDominates(Exported({0.2}, 0.0, 0, 1161.5, -1),
                                  Exported({0.3}, 0.0, 0, 1184.5, 0), none));
  EXPECT_FALSE(TighterSetDominates(Exported({0.2}, 0.0, 0, 1161.5, -1),
                                   Exported({0.3}, 0.0, 0, 1161.5, 0), none));
  // The tighter set must be within the looser budget: its clean-lap loss and, where the budget
  // limits them, its activations; a set that aborts a clean lap never is.
  EXPECT_TRUE(TighterSetDominates(Exported({0.2}, 0.2, 0, 1000.0, 0),
                                  Exported({0.3}, 0.1, 0, 1100.0, 0), quarter));
  EXPECT_FALSE(TighterSetDominates(Exported({0.2}, 0.3, 0, 1000.0, 0),
                                   Exported({0.3}, 0.1, 0, 1100.0, 0), quarter));
  EXPECT_FALSE(TighterSetDominates(Exported({0.2}, INFINITY, 0, 1000.0, 0),
                                   Exported({0.3}, 0.1, 0, 1100.0, 0), none));
  CleanLapBudget limited = quarter;
  limited.interventions = true;
  EXPECT_FALSE(TighterSetDominates(Exported({0.2}, 0.0, 1, 1000.0, 0),
                                   Exported({0.3}, 0.0, 0, 1100.0, 0), limited));
  EXPECT_TRUE(TighterSetDominates(Exported({0.2}, 0.0, 0, 1000.0, 0),
                                  Exported({0.3}, 0.0, 0, 1100.0, 0), limited));
  // No exported set (nothing to take).
  EXPECT_FALSE(TighterSetDominates(Exported({}, 0.0, 0, 1000.0, 0),
                                   Exported({0.3}, 0.0, 0, 1100.0, 0), none));
}

}  // namespace
}  // namespace scw::tuning
