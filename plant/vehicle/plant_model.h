// The plant interface: what a run's control loop, its observers and its traces need of a plant.
// scw's reduced double track (plant::Vehicle, plant/vehicle/vehicle.h) is one implementation;
// Open-Car-Dynamics behind its adapter (plant::ocd::OcdVehicle, plant/ocd/ocd_vehicle.h, built
// only when OCD is found) is the other. The scenario key plant.model chooses one per run
// (tuning/sim/plant_choice.h).
//
// Contract (checked at compile time by the concept PlantModel; a plant P provides):
//   p.params()              the vehicle file it was built from (params::VehicleParams)
//   p.time_step()           its step h [s]: Step advances the state by exactly h
//   p.contact_x/_y()        body-frame tyre contact points from the CoG [m] (x forward, y left),
//                           for the road-friction lookup under each wheel
//   p.MakeState(ic)         a state at the start condition ic (allocates; per run). Its type
//                           derives from plant::State, whose fields every plant fills with the same
//                           meaning and units (plant/vehicle/vehicle.h, struct State):
//                             time; x in StateIndex layout for pose, body velocities, wheel speeds
//                             and the relaxed slips fed to the tyres; the actuator and gearbox
//                             states; throttle; out (the step's diagnostics: specific force, loads,
//                             tyre-frame forces, slips, brake torques, engine and axle torque);
//                             status (kStatusNonFinite freezes the state at its last finite value).
//                           A plant with state of its own (an external model's instance) keeps it
//                           in the derived part, so one immutable plant serves parallel runs.
//   p.Step(u, &s)           one step on the nominal road in still air
//   p.Step(u, env, &s)      one step in `env` (per-wheel road friction, wind); the default
//                           Environment gives the step above
//   p.Measure(s, noise)     the sensors: plant::Measurement (plant/sensors/measurement.h), with
//                           sensor noise (plant/sensors/sensor_noise.h) when `noise` is given
// Step and Measure are noexcept and deterministic: the same inputs give bit-identical states on
// any thread. The loop calls them through templates (tuning/sim/control_loop.h), so scw's plant
// runs exactly the instructions it ran before the interface existed.
#pragma once

#include <concepts>
#include <type_traits>
#include <utility>

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_params.h"
#include "plant/sensors/measurement.h"
#include "plant/sensors/sensor_noise.h"
#include "plant/vehicle/environment.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {

/// The state type of plant P (what its MakeState returns).
template <class P>
using StateOf = std::remove_cvref_t<decltype(std::declval<const P&>().MakeState(
    std::declval<const InitialCondition&>()))>;

template <class P>
concept PlantModel = std::derived_from<StateOf<P>, State> &&
    requires(const P& p, const Actuators& u, const Environment& env, StateOf<P>* s,
             const StateOf<P>& cs, SensorNoiseState* noise) {
  { p.params() } -> std::same_as<const params::VehicleParams&>;
  { p.time_step() } -> std::convertible_to<double>;
  { p.contact_x() } -> std::same_as<const PerWheel<double>&>;
  { p.contact_y() } -> std::same_as<const PerWheel<double>&>;
  { p.Step(u, s) }
  noexcept;
  { p.Step(u, env, s) }
  noexcept;
  { p.Measure(cs, noise) }
  noexcept->std::same_as<Measurement>;
};

static_assert(PlantModel<Vehicle>, "plant::Vehicle must satisfy the plant interface");

}  // namespace scw::plant
