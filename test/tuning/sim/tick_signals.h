// Synthetic control ticks for the observer tests: the signals one tick of the closed loop would
// produce, owned by the test, viewed as a TickRecord the way the loop builds one.
#pragma once

#include "tuning/sim/tick_record.h"

namespace scw::tuning::synthetic {

struct TickSignals {
  double t = 0.0;
  int lap = 0;
  double s = 0.0, n = 0.0;
  double beta = 0.0, speed = 0.0;
  unsigned event_mask = 0;
  plant::Measurement meas;
  controller::motion::MotionOutput motion;
  controller::StabilityInput input;
  controller::StabilityOutput output;
  plant::StepOutputs plant;

  /// Valid while this object lives and is not moved.
  TickRecord Record() const {
    return {.t = t,
            .lap = lap,
            .s = s,
            .n = n,
            .beta = beta,
            .speed = speed,
            .event_mask = event_mask,
            .meas = meas,
            .motion = motion,
            .input = input,
            .output = output,
            .plant = plant};
  }
};

}  // namespace scw::tuning::synthetic
