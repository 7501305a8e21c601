#include "tuning/replay/log_setup.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <system_error>
#include <type_traits>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "tuning/replay/controller_log.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning::replay {

std::string SetupPathFor(const std::string& log_path) { return log_path + ".setup.yaml"; }

ControllerLogSetup ClosedLoopSetup(const ResolvedScenario& sc,
                                   const params::StabilityParams& stability) {
  const params::StabilityParams used = PrepareStability(sc, stability);
  ControllerLogSetup s;
  s.source = "scw simulate, scenario " + sc.spec.name + " (" + sc.source + ")";
  s.stability_file = sc.spec.stability;
  s.vehicle_file = sc.spec.vehicle;
  s.subsystems = sc.spec.subsystems;
  s.vehicle = used.vehicle;
  s.tires = used.tires;
  return s;
}

std::string SetupYaml(const ControllerLogSetup& setup, const std::string& log_path) {
  const std::string header =
      "Setup of the controller log " + std::filesystem::path(log_path).filename().string() +
      ": what its stability controller used besides the params file\n"
      "(vehicle constants, subsystem switches). scw replay applies it by default; "
      "docs/replay.md.";
  return params::ToPlainYaml(setup, header);
}

std::string CommitWithSetup(ControllerLogWriter& log, ControllerLogSetup setup) {
  if (!log.is_file()) {
    log.Commit();
    return "";
  }
  setup.log_rows = static_cast<int>(log.rows());
  setup.log_bytes = static_cast<double>(log.bytes());
  const std::string path = SetupPathFor(log.path());
  io::WriteFileAtomic(path, SetupYaml(setup, log.path()));
  try {
    log.Commit();
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(path, ec);  // no setup file without its log
    throw;
  }
  return path;
}

ControllerLogSetup LoadSetup(const std::string& path) {
  return params::LoadPlainFile<ControllerLogSetup>(path);
}

void CheckSetupMatchesLog(const ControllerLogSetup& setup, const std::string& setup_path,
                          const std::string& log_path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(log_path, ec)) return;  // FIFO, device: cannot tell
  const auto size = std::filesystem::file_size(log_path, ec);
  if (ec || static_cast<double>(size) == setup.log_bytes) return;
  throw ConfigError(setup_path, "log_bytes",
                    "this setup belongs to a log of " + params::FormatNumber(setup.log_bytes) +
                        " bytes, but " + log_path + " has " + std::to_string(size) +
                        " (written again or edited since?): delete the setup file, or replay with "
                        "--no-log-setup (and --vehicle FILE for the vehicle constants)");
}

params::StabilityParams WithRecordedVehicle(params::StabilityParams p,
                                            const std::set<std::string>& present,
                                            const ControllerLogSetup& setup) {
  auto is_vehicle_key = [](const std::string& path) {
    return path.rfind("vehicle.", 0) == 0 || path.rfind("tires.", 0) == 0;
  };
  std::map<std::string, void*> slots;
  params::ForEachField(
      p, [&](const std::string& path, auto& value, const params::Meta&) { slots[path] = &value; });
  params::StabilityParams recorded = p;
  recorded.vehicle = setup.vehicle;
  recorded.tires = setup.tires;
  params::ForEachField(recorded,
                       [&](const std::string& path, const auto& value, const params::Meta&) {
                         if (!is_vehicle_key(path) || present.count(path)) return;
                         const auto it = slots.find(path);
                         if (it == slots.end())
                           return;  // not declared for this wheel (rear velocity scaling)
                         *static_cast<std::decay_t<decltype(value)>*>(it->second) = value;
                       });
  return p;
}

}  // namespace scw::tuning::replay
