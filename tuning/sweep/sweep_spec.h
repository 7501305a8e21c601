// Parse: the `scw sweep` arguments as text → a SweepDefinition (axes, configurations, base
// overrides), and the `--trace-at` conditions → TraceConditions. Pure: no file is read and no
// scenario key is checked here (ExpandSweep, sweep_plan.h, checks them against the schema).
//
// Vocabulary (see sweep.h for the whole sweep)
//   axis           one varied scenario key with its values, from `--vary key=v1,v2,...` or
//                  `--vary key=start:step:stop` (values kept as text: they are `--set` values)
//   configuration  a named set of overrides, from `--config name:key=v,key=v` (e.g. the four
//                  ESC/CS combinations); no configuration = one configuration "default"
//
// Errors: ConfigError whose problem is named after the argument as given on the command line
// ("--vary gg_scale=1:0:2: the step of start:step:stop must not be 0").
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::tuning::sweep {

struct SweepAxis {
  std::string key;                  ///< dotted scenario key, e.g. gg_scale
  std::vector<std::string> values;  ///< `--set` values, e.g. "1.05"
};

struct SweepConfig {
  std::string name;                    ///< [A-Za-z0-9_.+-]+ (file names, CSV)
  std::vector<std::string> overrides;  ///< "key=value"
};

/// Everything that defines a sweep's grid (the runs, not where or how they execute).
struct SweepDefinition {
  std::string scenario_file;                ///< "" = the built-in default scenario
  std::vector<std::string> base_overrides;  ///< `--set`
  std::string stability_file;               ///< "" = the scenario's
  std::vector<SweepAxis> axes;
  std::vector<SweepConfig> configs;  ///< empty = one configuration "default"
  bool stop_at_first_abort = false;
};

/// Parses `key=v1,v2,...` (commas inside [...] do not split: list values) or
/// `key=start:step:stop` (inclusive stop, within 1e-9 of a step; values printed with the decimals
/// of the arguments, e.g. 1.0:0.05:1.2 → 1, 1.05, 1.1, 1.15, 1.2). The key is not checked here
/// (see ValidateSweep). Throws ConfigError with source "--vary <arg>" saying what is wrong.
SweepAxis ParseVary(const std::string& arg);

/// Parses `name:key=v,key=v` (or just `name` for no overrides). Throws ConfigError with source
/// "--config <arg>".
SweepConfig ParseConfig(const std::string& arg);

/// The `scw sweep` arguments that define the grid, as given.
struct SweepArguments {
  std::string scenario;                ///< --scenario ("" = built-in)
  std::vector<std::string> overrides;  ///< --set
  std::string stability;               ///< --stability
  std::vector<std::string> vary;       ///< --vary, in order (the first is the series axis)
  std::vector<std::string> configs;    ///< --config, in order
  bool stop_at_first_abort = false;
};

/// The definition of `a`. Throws one ConfigError (source "scw sweep") listing every malformed
/// --vary and --config, each problem named after its argument ("--vary gg_scale").
SweepDefinition ParseSweepArguments(const SweepArguments& a);

/// One `--trace-at` key with its accepted values (any one may match).
struct TraceCondition {
  int axis = -1;  ///< index into the axes; -1 = the configuration name
  std::vector<std::string> values;
};

/// Parses `--trace-at key=value` conditions (key: `config` or a varied key), one TraceCondition
/// per distinct key in the order first given. Throws one ConfigError (source "scw sweep") naming
/// every malformed condition ("--trace-at <arg>") and every key that is neither.
std::vector<TraceCondition> ParseTraceConditions(const std::vector<SweepAxis>& axes,
                                                 const std::vector<std::string>& at);

/// Whether `have` and `want` name the same value: numerically (within 1e-9, relative) when both
/// are numbers, else as text. So `--trace-at gg_scale=1.0` selects the value "1".
bool SameSweepValue(const std::string& have, const std::string& want);

}  // namespace scw::tuning::sweep
