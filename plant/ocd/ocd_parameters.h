// The one mapping of an scw vehicle file (params/schema/vehicle_params.h) onto the parameters of
// Open-Car-Dynamics (OCD) in the composition the adapter runs (plant/ocd/ocd_vehicle.h): its
// double track with MF5.2 tyres and the default aerodynamics, its RWD drivetrain with
// limited-slip differential, and the integration step.
//
// Contract
//   MapVehicle(p) lists every OCD parameter the adapter sets, by OCD's own name (as OCD declares it
//   through param_management_cpp and lists it in python3/ocd_vehicle_models_py/config/*.json), with
//   its value and where the value comes from:
//     - a vehicle-file key (its dotted path, or a formula over several), or
//     - for a quantity OCD has and the vehicle file does not (unsprung masses, roll and pitch
//       inertia, suspension springs, dampers, anti-roll bars, roll and pitch centres, tyre vertical
//       stiffness, the MF5.2 camber and scaling coefficients outside scw's fit): the value, its
//       public source and why.
//   Quantities the adapter keeps out of OCD on purpose are not in the list: the engine, gearbox,
//   clutch, brake hydraulics and steering actuator stay scw's (plant/powertrain, plant/actuator)
//   and drive OCD through its public inputs; the sensors stay scw's (plant/sensors).
//   CheckRepresentable(p) names every vehicle-file value OCD cannot represent (an MF fall-off other
//   than 1, slip kinematics other than OCD's built-in ones, gravity other than OCD's 9.81 m/s^2, an
//   LSD speed scale other than OCD's 1 rad/s): running such a car on OCD is a configuration error,
//   never a silent drop. Replaced(p) names the keys whose quantity OCD models with its own
//   structure (the lagged load transfer is OCD's sprung body on springs; the wind side force is
//   OCD's lateral drag; a spool is OCD's LSD with a stiff preload): a run on OCD says so.
//   MappingTableMarkdown(p) is the table of docs/ocd-plant.md, generated from the same list.
// Units: SI, as OCD's names say (_kg, _m, _Npm, ...). Pure functions; no OCD header is needed.
// Sources: ../shared/spec/plant-and-track.md §2 (OCD's model), §4.1 and
// ../shared/data/vehicles/README.md (the AV-21 "il" set of TUM's sim_vehicle_dynamics, the only
// public near-complete parameter set of a Dallara car of this class).
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/vehicle_params.h"

namespace scw::plant::ocd {

/// One OCD parameter as the adapter sets it.
struct OcdParameter {
  std::string name;           ///< OCD's name, e.g. vehicle_dynamics_double_track.mass_vehicle_kg
  std::vector<double> value;  ///< one number, or the entries of an array parameter
  std::string source;         ///< vehicle-file key(s) or formula; for OCD-only values the source
  bool ocd_only = false;      ///< the vehicle file has no such quantity
  std::string why;            ///< for OCD-only values: why this value
};

/// OCD's four tyre-model instances, by OCD's wheel names (FL, FR, RL, RR).
inline constexpr const char* kOcdWheelNames[4] = {"front_left", "front_right", "rear_left",
                                                  "rear_right"};

// OCD's built-in slip kinematics (vehicle_dynamics_equations_impl.hpp): the values the vehicle
// file's tires.kinematics must have for a run on OCD.
inline constexpr double kOcdRelaxationLengthLong = 0.3;  // [m]
inline constexpr double kOcdRelaxationLengthLat = 0.2;   // [m]
inline constexpr double kOcdRelaxationSpeedMin = 10.0;   // [m/s]
inline constexpr double kOcdSlipSpeedMinLong = 3.0;      // [m/s]
inline constexpr double kOcdSlipSpeedMinLat = 1.0;       // [m/s]
inline constexpr double kOcdSlipLimit = 1.0;             // [-]
inline constexpr double kOcdGravity = 9.81;              // [m/s^2], OCD's G_CONST
inline constexpr double kOcdLsdSpeedScale = 1.0;         // [rad/s]: OCD's tanh(omega_diff)
/// Preload [N*m] that stands in for a spool on OCD's LSD: stiff enough to hold the rear wheels
/// within ~0.1 rad/s of each other at full drive torque, soft enough for a stable 1 ms step.
inline constexpr double kOcdSpoolPreload = 3000.0;

/// Every OCD parameter the adapter sets for vehicle `p`, in OCD's declaration order (drivetrain,
/// integration step, vehicle dynamics, aerodynamics, the four tyre models).
std::vector<OcdParameter> MapVehicle(const params::VehicleParams& p);

/// The values of `p` OCD cannot represent, each with its vehicle-file path (empty: OCD can run it).
std::vector<Problem> CheckRepresentable(const params::VehicleParams& p);

/// The vehicle-file keys whose quantity OCD models by its own structure, as one line per group
/// (what replaces them); empty when none applies.
std::vector<std::string> Replaced(const params::VehicleParams& p);

/// The mapping as a Markdown table (OCD parameter, value, scw source or public source and why),
/// the tyre models' coefficients grouped per axle.
std::string MappingTableMarkdown(const params::VehicleParams& p);

}  // namespace scw::plant::ocd
