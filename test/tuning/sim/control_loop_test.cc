// The shared control loop (tuning/sim/control_loop.h): the order of a tick's steps, the plant
// steps per tick with and without an environment, and how a driver ends the run.
#include "tuning/sim/control_loop.h"

#include <gtest/gtest.h>

#include <string>

#include "params/schema/stability_params.h"
#include "params/schema/vehicle_params.h"

namespace scw::tuning {
namespace {

struct Fixture {
  params::VehicleParams vp;
  plant::Vehicle car{vp};
  controller::StabilityController ctl{params::StabilityParams{}};
  plant::State st = car.MakeState({0.0, 0.0, 0.0, 20.0});
  controller::StabilityController::State cs;
  ControlLoop<plant::Vehicle> Loop(long ratio) {
    return ControlLoop<plant::Vehicle>{car, ctl, ratio, &st, nullptr, &cs};
  }
};

// Records the calls; ends the run in Output at tick `last`; a non-nominal environment on odd
// ticks.
struct Recorder {
  long last = 2;
  std::string log;
  long env_calls = 0;
  bool Begin(long k) {
    log += "B" + std::to_string(k);
    return true;
  }
  bool Finite(const plant::Measurement&) {
    log += "F";
    return true;
  }
  void NonFinite() { log += "N"; }
  bool Input(long, const plant::Measurement&, controller::StabilityInput* in) {
    log += "I";
    in->v_x = 20.0;
    return true;
  }
  bool Output(long k, const plant::Measurement&, const controller::StabilityInput&,
              const controller::StabilityOutput&, const plant::StepOutputs&) {
    log += "O";
    odd = k % 2 == 1;
    return k < last;
  }
  bool Environment(const plant::State&, plant::Environment* env) {
    ++env_calls;
    env->mu = {0.9, 0.9, 0.9, 0.9};
    return odd;
  }
  void End(long) { log += "E"; }
  bool odd = false;
};

TEST(ControlLoopTest, TicksRunInOrderAndTheDriverEndsTheRun) {
  Fixture f;
  Recorder r;
  const double t0 = f.st.time;
  f.Loop(10).Run(r);
  EXPECT_EQ(r.log, "B0FIOEB1FIOEB2FIO");
  EXPECT_EQ(r.env_calls, 20);  // ratio plant steps in each of the two completed ticks
  EXPECT_NEAR(f.st.time - t0, 20 * f.car.time_step(), 1e-12);
}

TEST(ControlLoopTest, BeginAndInputEndTheRunBeforeThePlantSteps) {
  struct StopAtBegin : Recorder {
    bool Begin(long k) {
      log += "B" + std::to_string(k);
      return k < 1;
    }
  };
  Fixture f;
  StopAtBegin r;
  r.last = 100;
  f.Loop(2).Run(r);
  EXPECT_EQ(r.log, "B0FIOEB1");
  EXPECT_EQ(r.env_calls, 2);
}

TEST(ControlLoopTest, ANonFiniteStateEndsTheRunThroughTheDriver) {
  Fixture f;
  f.st.status |= plant::kStatusNonFinite;
  Recorder r;
  f.Loop(1).Run(r);
  EXPECT_EQ(r.log, "B0N");
}

}  // namespace
}  // namespace scw::tuning
