// Scenario events (tuning/sim/events.h): where they fire, what they do, and the late-braking
// reference.
#include "tuning/sim/events.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "params/schema/scenario_params.h"
#include "plant/track/corners.h"
#include "plant/track/yas_north.h"

namespace scw::tuning {
namespace {

const plant::Track& Yas() {
  static const plant::Track t = plant::YasNorthTrack();
  return t;
}

TEST(EventsTest, ListsMustMatchAndCornersAndLapsBeWholeNumbers) {
  params::ScenarioParams sc;
  sc.events.throttle.s = {100.0, 200.0};
  sc.events.throttle.corner = {0.0, 1.5};
  sc.events.throttle.lap = {1.0};
  sc.events.throttle.duration = {1.0, 1.0};
  sc.events.throttle.value = {1.0, 1.0};
  const Problems pr = params::Validate(sc);
  std::string all;
  for (const auto& p : pr.items()) all += p.path + ": " + p.message + "\n";
  EXPECT_NE(all.find("events.throttle.lap: needs one value per event (2 as in s), has 1"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("events.throttle.corner: element [1] must be a whole number"),
            std::string::npos)
      << all;
  sc.events.throttle.lap = {1.0, 0.0};
  sc.events.throttle.corner = {0.0, 1.0};
  EXPECT_TRUE(params::Validate(sc).empty());
}

TEST(EventsTest, ATimedEventFiresWhenTheCarPassesItsPlaceOnItsLapAndLastsItsDuration) {
  params::ScenarioEvents ev;
  ev.throttle = {{0.0}, {500.0}, {2.0}, {0.5}, {0.9}};  // corner, s, lap, duration, value
  ev.steer = {{0.0, 0.0}, {500.0, 500.0}, {0.0, 0.0}, {1.0, 1.0}, {0.01, 0.02}};
  const EventSchedule sched(ev, Yas());
  auto st = sched.MakeState();
  // Lap 1: the throttle fault is for lap 2; the steer offsets fire on every lap and add up.
  sched.Update(499.0, 501.0, 1, 10.0, &st);
  EventSchedule::Active a = sched.At(10.0, st);
  EXPECT_FALSE(a.throttle_fault);
  EXPECT_DOUBLE_EQ(a.steer_offset, 0.03);
  EXPECT_EQ(a.mask, 2u);
  EXPECT_EQ(sched.At(11.0, st).mask, 0u);  // lasted its second
  // Lap 2: both fire; passing again on the same lap fires nothing new.
  sched.Update(499.5, 500.5, 2, 80.0, &st);
  a = sched.At(80.2, st);
  EXPECT_TRUE(a.throttle_fault);
  EXPECT_EQ(a.throttle, 0.9);
  EXPECT_EQ(sched.At(80.6, st).mask, 2u);  // throttle over after 0.5 s, steer still on
  sched.Update(499.5, 500.5, 2, 85.0, &st);
  EXPECT_EQ(sched.At(85.0, st).mask, 0u);
  // Crossing the start line wraps; a jump over half the track (a reset) fires nothing.
  params::ScenarioEvents at_line;
  at_line.rear_grip = {{0.0}, {1.0}, {0.0}, {1.0}, {0.5}};
  const EventSchedule s2(at_line, Yas());
  auto st2 = s2.MakeState();
  s2.Update(Yas().length() - 2.0, 3.0, 2, 5.0, &st2);
  EXPECT_EQ(s2.At(5.0, st2).rear_grip, 0.5);
  auto st3 = s2.MakeState();
  s2.Update(0.5, 1500.0, 1, 5.0, &st3);
  EXPECT_EQ(s2.At(5.0, st3).rear_grip, 1.0);
}

TEST(EventsTest, AGustRisesAndFallsAsOneMinusCosineFromTheSideItComesFrom) {
  params::ScenarioEvents ev;
  ev.gust = {{0.0}, {100.0}, {0.0}, {2.0}, {20.0}, {90.0}};  // from the left
  const EventSchedule sched(ev, Yas());
  auto st = sched.MakeState();
  sched.Update(99.0, 101.0, 1, 0.0, &st);
  const auto peak = sched.At(1.0, st);
  EXPECT_NEAR(std::hypot(peak.wind_x, peak.wind_y), 20.0, 1e-9);
  EXPECT_NEAR(std::hypot(sched.At(0.5, st).wind_x, sched.At(0.5, st).wind_y), 10.0, 1e-9);
  // Blowing to the right of the track direction: the cross product track × wind is negative.
  const double psi = Yas().PoseAt(100.0).heading;
  EXPECT_LT(std::cos(psi) * peak.wind_y - std::sin(psi) * peak.wind_x, -19.99);
  EXPECT_EQ(sched.At(2.0, st).mask, 0u);
}

}  // namespace
}  // namespace scw::tuning
