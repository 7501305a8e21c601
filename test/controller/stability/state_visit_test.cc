// Controller state described once (controller/common/state_visit.h): every State struct's Visit
// lists as many members as the struct has (counted at compile time), and the state guard built
// on it rejects a non-finite value in any listed real, including those the old hand-written guard
// missed.
#include "controller/common/state_visit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "controller/stability/stability_controller.h"
#include "test/common/field_count.h"

namespace scw::controller {
namespace {

/// Counts the top-level members a Visit lists (nested states count once).
struct MemberCounter {
  std::size_t n = 0;
  template <class T>
  void Real(const T&) {
    ++n;
  }
  template <class T>
  void Reals(const T&) {
    ++n;
  }
  template <class T>
  void Time(const T&) {
    ++n;
  }
  template <class T>
  void Discrete(const T&) {
    ++n;
  }
  template <class T>
  void Buffer(const T&) {
    ++n;
  }
  template <class T>
  void Nested(const T&) {
    ++n;
  }
  template <class T>
  void NestedEach(const T&) {
    ++n;
  }
};

template <class S>
std::size_t Listed() {
  const S s{};
  MemberCounter c;
  S::Visit(s, c);
  return c.n;
}

TEST(StateVisitTest, EveryStateStructListsEachMember) {
  EXPECT_EQ(Listed<PidState>(), test::FieldCount<PidState>());
  EXPECT_EQ(Listed<SlipEstimator::State>(), test::FieldCount<SlipEstimator::State>());
  EXPECT_EQ(Listed<Esc::State>(), test::FieldCount<Esc::State>());
  EXPECT_EQ(Listed<Countersteer::State>(), test::FieldCount<Countersteer::State>());
  EXPECT_EQ(Listed<AbsWheelController::State>(), test::FieldCount<AbsWheelController::State>());
  EXPECT_EQ(Listed<TcWheelController::State>(), test::FieldCount<TcWheelController::State>());
  EXPECT_EQ(Listed<SlipControl::State>(), test::FieldCount<SlipControl::State>());
  EXPECT_EQ(Listed<StabilityController::State>(), test::FieldCount<StabilityController::State>());
}

TEST(StateVisitTest, GuardRejectsANonFiniteValueAnywhere) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const StabilityController::State initial;
  EXPECT_TRUE(StateFinite(initial));  // time stamps start at −∞ ("never"): valid
  auto broken = [&](auto mutate) {
    StabilityController::State s;
    mutate(s);
    return !StateFinite(s);
  };
  EXPECT_TRUE(broken([&](auto& s) { s.esc.pid_psi.filtered_prev = nan; }));  // missed before
  EXPECT_TRUE(broken([&](auto& s) { s.esc.pid_beta.integrator = inf; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip.blend_filtered = nan; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip_control.abs[kRL].v_latched = nan; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip_control.tc[kFR].force_prev = -inf; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip_control.tc[kRR].t_exceed = nan; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip_control.t_gear = nan; }));
  EXPECT_TRUE(broken([&](auto& s) { s.slip_control.slip_angle_filtered[kFL] = inf; }));
  EXPECT_TRUE(broken([&](auto& s) { s.countersteer.alpha_rear_filtered = nan; }));
  EXPECT_FALSE(broken([&](auto& s) { s.slip_control.t_gear = 12.5; }));
}

}  // namespace
}  // namespace scw::controller
