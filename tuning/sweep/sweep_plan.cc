#include "tuning/sweep/sweep_plan.h"

#include <filesystem>
#include <map>

#include "params/io/write.h"
#include "params/schema/field.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning::sweep {
namespace {

namespace fs = std::filesystem;

std::string VaryText(const SweepAxis& a) {
  std::string s = "--vary " + a.key + "=";
  for (std::size_t i = 0; i < a.values.size(); ++i) s += (i ? "," : "") + a.values[i];
  return s;
}

std::string ConfigText(const SweepConfig& c) {
  std::string s = "--config " + c.name;
  for (std::size_t i = 0; i < c.overrides.size(); ++i) s += (i ? "," : ":") + c.overrides[i];
  return s;
}

std::string FirstProblems(const ConfigError& e) {
  std::string out;
  for (const auto& p : e.problems()) {
    if (!out.empty()) out += "; ";
    out += p.path.empty() ? p.message : p.path + ": " + p.message;
  }
  return out.empty() ? std::string(e.what()) : out;
}

params::ScenarioParams BaseScenario(const SweepDefinition& d,
                                    const std::vector<std::string>& overrides) {
  params::ScenarioParams spec = d.scenario_file.empty() ? DefaultScenario(overrides)
                                                        : LoadScenario(d.scenario_file, overrides);
  if (!d.stability_file.empty()) spec.stability = fs::absolute(d.stability_file).string();
  return spec;
}

/// The scenario with the keys only the closed loop reads reset: equal texts resolve equally.
std::string ResolveKey(params::ScenarioParams spec) {
  const params::ScenarioParams defaults;
  spec.name = defaults.name;
  spec.subsystems = defaults.subsystems;
  spec.abort = defaults.abort;
  spec.laps = defaults.laps;
  return params::ToPlainYaml(spec);
}

}  // namespace

std::vector<GridPoint> ExpandGrid(const std::vector<SweepAxis>& axes, int n_configs) {
  std::vector<GridPoint> out;
  const std::size_t n_axes = axes.size();
  for (const auto& a : axes)
    if (a.values.empty()) return out;
  // Axes 2..n as a mixed-radix number (last axis fastest), the first axis innermost.
  long outer = 1;
  for (std::size_t i = 1; i < n_axes; ++i) outer *= static_cast<long>(axes[i].values.size());
  const int n_first = n_axes ? static_cast<int>(axes[0].values.size()) : 1;
  int series = 0;
  for (int c = 0; c < n_configs; ++c) {
    for (long o = 0; o < outer; ++o, ++series) {
      std::vector<int> idx(n_axes, 0);
      long rest = o;
      for (std::size_t i = n_axes; i-- > 1;) {
        const long size = static_cast<long>(axes[i].values.size());
        idx[i] = static_cast<int>(rest % size);
        rest /= size;
      }
      for (int k = 0; k < n_first; ++k) {
        GridPoint p;
        p.config = c;
        p.value = idx;
        if (n_axes) p.value[0] = k;
        p.series = series;
        out.push_back(std::move(p));
      }
    }
  }
  return out;
}

params::ScenarioParams PointScenario(const SweepDefinition& d, const GridPoint& p) {
  std::vector<std::string> o = d.base_overrides;
  if (!d.configs.empty()) {
    const auto& c = d.configs[static_cast<std::size_t>(p.config)];
    o.insert(o.end(), c.overrides.begin(), c.overrides.end());
  }
  for (std::size_t i = 0; i < d.axes.size(); ++i)
    o.push_back(d.axes[i].key + "=" + d.axes[i].values[static_cast<std::size_t>(p.value[i])]);
  return BaseScenario(d, o);
}

void ValidateSweep(const SweepDefinition& d) {
  // The base scenario first: its errors name the file or --set themselves.
  (void)BaseScenario(d, d.base_overrides);
  Problems problems;
  for (std::size_t i = 0; i < d.configs.size(); ++i) {
    const auto& c = d.configs[i];
    for (std::size_t j = 0; j < i; ++j)
      if (d.configs[j].name == c.name)
        problems.Add(ConfigText(c), "configuration name '" + c.name + "' is used twice");
    std::vector<std::string> o = d.base_overrides;
    o.insert(o.end(), c.overrides.begin(), c.overrides.end());
    try {
      (void)BaseScenario(d, o);
    } catch (const ConfigError& e) {
      problems.Add(ConfigText(c), FirstProblems(e));
    }
  }
  for (std::size_t i = 0; i < d.axes.size(); ++i) {
    const auto& a = d.axes[i];
    for (std::size_t j = 0; j < i; ++j)
      if (d.axes[j].key == a.key) problems.Add(VaryText(a), "key '" + a.key + "' is varied twice");
    for (std::size_t k = 0; k < a.values.size(); ++k) {
      for (std::size_t j = 0; j < k; ++j)
        if (a.values[j] == a.values[k])
          problems.Add(VaryText(a), "value '" + a.values[k] + "' is given twice");
      std::vector<std::string> o = d.base_overrides;
      o.push_back(a.key + "=" + a.values[k]);
      try {
        (void)BaseScenario(d, o);
      } catch (const ConfigError& e) {
        problems.Add(VaryText(a), FirstProblems(e));
        break;  // one message per argument
      }
    }
  }
  if (!problems.empty()) throw ConfigError("scw sweep", problems.items());
}

SweepPlan ExpandSweep(const SweepDefinition& d) {
  ValidateSweep(d);
  SweepPlan plan;
  plan.definition = d;
  plan.configs = d.configs.empty() ? std::vector<SweepConfig>{{"default", {}}} : d.configs;
  const std::vector<GridPoint> grid = ExpandGrid(d.axes, static_cast<int>(plan.configs.size()));
  plan.runs.resize(grid.size());
  // Scenarios (serially: cheap, and errors come out in run order), grouped by resolution.
  std::map<std::string, int> resolve_index;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    PlannedRun& run = plan.runs[i];
    run.point = grid[i];
    run.spec = PointScenario(d, run.point);
    const auto [it, added] =
        resolve_index.emplace(ResolveKey(run.spec), static_cast<int>(plan.resolutions.size()));
    if (added) plan.resolutions.push_back(run.spec);
    run.resolution = it->second;
  }
  plan.base_dir =
      d.scenario_file.empty() ? std::string() : fs::path(d.scenario_file).parent_path().string();
  plan.source = d.scenario_file.empty() ? "built-in" : d.scenario_file;
  return plan;
}

}  // namespace scw::tuning::sweep
