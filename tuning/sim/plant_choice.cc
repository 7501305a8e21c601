#include "tuning/sim/plant_choice.h"

namespace scw::tuning {

std::string NoOcdMessage() {
  return "'ocd' (Open-Car-Dynamics) is not in this build of scw: configure it with "
         "-DSCW_WITH_OCD=ON and -DSCW_OCD_SOURCE_DIR=<Open-Car-Dynamics folder> (docs/ocd-plant.md "
         "says where to get it), or run plant.model=scw";
}

void CheckPlantModel(const std::string& model, const params::VehicleParams& vehicle,
                     const std::string& where) {
  if (model == "scw") return;
  if (model != "ocd")
    throw ConfigError(where, "plant.model", "'" + model + "' is not one of scw|ocd");
#if SCW_WITH_OCD
  const std::vector<Problem> problems = plant::ocd::CheckRepresentable(vehicle);
  if (!problems.empty()) throw ConfigError(where + " (plant.model=ocd)", problems);
#else
  (void)vehicle;
  throw ConfigError(where, "plant.model", NoOcdMessage());
#endif
}

std::vector<std::string> PlantNotes(const std::string& model,
                                    const params::VehicleParams& vehicle) {
#if SCW_WITH_OCD
  if (model == "ocd") return plant::ocd::Replaced(vehicle);
#else
  (void)model;
  (void)vehicle;
#endif
  return {};
}

PlantChoice::PlantChoice(const std::string& model, const params::VehicleParams& vehicle)
    : model_(model) {
  CheckPlantModel(model, vehicle, vehicle.name);
#if SCW_WITH_OCD
  if (model == "ocd") {
    ocd_.emplace(vehicle);
    return;
  }
#endif
  scw_.emplace(vehicle);
}

double PlantChoice::time_step() const noexcept {
  return Visit([](const auto& p) { return p.time_step(); });
}

}  // namespace scw::tuning
