// The one step loop of every simulated run: the car (plant, sensors) and the stability controller
// advanced control tick by control tick. The closed loop (tuning/sim/closed_loop.h: motion
// controller, request path, lap observers) and the standard maneuvers
// (tuning/maneuver/maneuver.h: the driving robot's programs) are two drivers of this loop; what
// touches the plant model is here only, so every plant serves both: the loop is a template on the
// plant (plant/vehicle/plant_model.h: scw's plant::Vehicle, or Open-Car-Dynamics behind
// plant::ocd::OcdVehicle), chosen per run by the scenario's plant.model
// (tuning/sim/plant_choice.h).
//
// One control tick k (period tS; the plant steps `ratio` = tS/h times per tick):
//   1. d.Begin(k)                            false: the run ends before this tick
//   2. m = vehicle.Measure(state, noise)     the sensors (seeded noise when enabled)
//   3. state non-finite or !d.Finite(m)      d.NonFinite(), the run ends
//   4. d.Input(k, m, &in)                    the controller's input; false: the run ends
//   5. out = stability.Step(in, &stability state)
//   6. d.Output(k, m, in, out, state.out)    the observers (state.out: the plant's outputs of its
//                                            last step); false: the run ends after this tick
//   7. ratio times: d.Environment(state, &env) ? vehicle.Step(u, env, &state)
//                                              : vehicle.Step(u, &state)   u = out's requests
//      (false: the nominal road in still air, the cheaper step bit for bit equal to the default
//      environment)
//   8. d.End(k)
// The driver is any type with these member functions (a template parameter, so the per-step
// calls inline); Environment receives the plant's state as a const plant::State& (every plant's
// state derives from it). The loop allocates nothing; it is deterministic and holds no state of its
// own: one Run per run, on any thread.
#pragma once

#include "controller/stability/stability_controller.h"
#include "plant/sensors/measurement.h"
#include "plant/sensors/sensor_noise.h"
#include "plant/vehicle/environment.h"
#include "plant/vehicle/plant_model.h"
#include "plant/vehicle/vehicle.h"

namespace scw::tuning {

/// The objects of one run that the loop advances (owned by the caller, outliving the run).
template <plant::PlantModel Plant>
struct ControlLoop {
  const Plant& vehicle;  ///< the plant model
  const controller::StabilityController& stability;
  long ratio = 1;                            ///< plant steps per control tick, >= 1
  plant::StateOf<Plant>* state = nullptr;    ///< the plant's state
  plant::SensorNoiseState* noise = nullptr;  ///< sensor noise state, nullptr: noise-free
  controller::StabilityController::State* stability_state = nullptr;

  /// Runs ticks k = 0, 1, ... until the driver ends the run (see the file comment).
  template <class Driver>
  void Run(Driver& d) const {
    for (long tick = 0;; ++tick) {
      if (!d.Begin(tick)) return;
      const plant::Measurement meas = vehicle.Measure(*state, noise);
      if ((state->status & plant::kStatusNonFinite) || !d.Finite(meas)) {
        d.NonFinite();
        return;
      }
      controller::StabilityInput in;
      if (!d.Input(tick, meas, &in)) return;
      const controller::StabilityOutput out = stability.Step(in, stability_state);
      if (!d.Output(tick, meas, in, out, state->out)) return;
      const plant::Actuators act{out.steering, out.brake_bar, out.throttle};
      for (long k = 0; k < ratio; ++k) {
        plant::Environment env;
        if (d.Environment(*state, &env))
          vehicle.Step(act, env, state);
        else
          vehicle.Step(act, state);
      }
      d.End(tick);
    }
  }
};

}  // namespace scw::tuning
