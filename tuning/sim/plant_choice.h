// The plant a run simulates the car with: the scenario key plant.model (params/schema/
// plant_variation_params.h) chooses scw's reduced double track (plant::Vehicle) or Open-Car-
// Dynamics behind its adapter (plant::ocd::OcdVehicle, plant/ocd/ocd_vehicle.h), which exists only
// in a build with OCD (CMake option SCW_WITH_OCD; the compile definition SCW_WITH_OCD is 1 there,
// 0 otherwise, the same in every translation unit that includes this header).
//
//   CheckPlantModel(model, vehicle, where)   at resolution time (tuning/sim/scenario.h): throws
//       ConfigError (path plant.model, or the vehicle-file keys OCD cannot represent) for a model
//       this build lacks or a car the model cannot run; what the model replaces goes to
//       PlantNotes.
//   PlantChoice(model, vehicle)              the plant object, immutable, shared by the runs
//   choice.Visit(f)                          calls f(plant) with the concrete plant type, so the
//       control loop (tuning/sim/control_loop.h) is compiled per plant: scw's plant runs the same
//       instructions as before the choice existed.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "params/schema/vehicle_params.h"
#include "plant/vehicle/vehicle.h"

#ifndef SCW_WITH_OCD
#error "SCW_WITH_OCD is scw::sim's public compile definition (0 or 1): link scw::sim"
#endif
#if SCW_WITH_OCD
#include "plant/ocd/ocd_vehicle.h"
#endif

namespace scw::tuning {

/// Whether this build has the Open-Car-Dynamics plant.
inline constexpr bool kHaveOcdPlant = SCW_WITH_OCD != 0;

/// The message of plant.model=ocd in a build without OCD.
std::string NoOcdMessage();

/// Throws ConfigError (file `where`) when `vehicle` cannot be simulated with plant `model` in this
/// build: an unknown model, ocd without OCD, or vehicle values OCD cannot represent.
void CheckPlantModel(const std::string& model, const params::VehicleParams& vehicle,
                     const std::string& where);

/// What plant `model` models with its own structure instead of the vehicle file's keys (one line
/// each; empty for scw's plant). For a note before a run.
std::vector<std::string> PlantNotes(const std::string& model, const params::VehicleParams& vehicle);

class PlantChoice {
 public:
  /// Builds the plant (throws ConfigError as CheckPlantModel).
  PlantChoice(const std::string& model, const params::VehicleParams& vehicle);

  double time_step() const noexcept;
  const std::string& model() const noexcept { return model_; }

  /// f(plant) with the chosen plant (const plant::Vehicle& or const plant::ocd::OcdVehicle&).
  template <class F>
  decltype(auto) Visit(F&& f) const {
#if SCW_WITH_OCD
    if (ocd_) return f(*ocd_);
#endif
    return f(*scw_);
  }

 private:
  std::string model_;
  std::optional<plant::Vehicle> scw_;
#if SCW_WITH_OCD
  std::optional<plant::ocd::OcdVehicle> ocd_;
#endif
};

}  // namespace scw::tuning
