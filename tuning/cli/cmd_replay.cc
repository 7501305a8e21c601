// scw replay — recorded controller inputs through the stability controller, open loop (issue 10,
// docs/replay.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

#include "controller/stability/stability_controller.h"
#include "params/io/load.h"
#include "params/schema/stability_params.h"
#include "tuning/cli/command.h"
#include "tuning/replay/replay.h"

namespace scw::cli {
namespace {

struct ReplayOptions {
  std::string log;
  std::string params;
  std::string compare;
  std::string out;
  std::string node = params::kStabilityNodeKey;
  bool release_compat = false;
  bool columns = false;
};

bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec) && !ec;
}

int RunReplay(const ReplayOptions& o) {
  if (o.columns) {
    std::cout << tuning::ColumnsMarkdown();
    return kExitOk;
  }
  // Checked here rather than by CLI11 so that --columns works alone.
  if (o.log.empty()) throw CLI::RequiredError("LOG");
  if (o.params.empty()) throw CLI::RequiredError("--params");
  if (!o.out.empty() && SameFile(o.out, o.log))
    throw ConfigError(o.out, "-o", "the output would overwrite the log; choose another file");
  params::StabilityOptions options;
  options.release_compat = o.release_compat;
  const controller::StabilityController a(
      params::LoadRosFile<params::StabilityParams>(o.params, o.node), options);

  if (o.compare.empty()) {
    const tuning::ReplaySummary s = tuning::ReplayLog(o.log, a, o.out);
    if (o.out.empty()) {
      std::cout << tuning::FormatSummary(s);
      if (o.release_compat) std::cout << "(release_compat: long_fx ignored, TC cannot activate)\n";
    } else {
      std::cerr << "wrote " << o.out << " (" << s.rows << " rows, " << s.invalid_rows
                << " invalid)\n";
    }
    return kExitOk;
  }

  const controller::StabilityController b(
      params::LoadRosFile<params::StabilityParams>(o.compare, o.node), options);
  const tuning::ComparisonSummary c = tuning::CompareOnLog(o.log, a, b, o.out);
  std::cout << tuning::FormatComparison(c, o.params, o.compare);
  if (o.release_compat) std::cout << "(release_compat: long_fx ignored, TC cannot activate)\n";
  if (!o.out.empty()) std::cerr << "wrote " << o.out << " (outputs of " << o.params << ")\n";
  return kExitOk;
}

void AddReplay(CLI::App& app) {
  auto o = std::make_shared<ReplayOptions>();
  auto* cmd = app.add_subcommand(
      "replay",
      "Run the stability controller open loop over a recorded controller log (CSV) and report "
      "where ESC, countersteer, ABS and TC intervene; --compare runs two parameter sets");
  cmd->footer(
      "Log format, output columns and the summary: docs/replay.md.\n"
      "Exit codes: 0 ok, 1 the output could not be written, 2 bad log, params file or "
      "arguments (the message names the line and column).");
  cmd->add_option("LOG", o->log, "Controller log (CSV, one row per controller step; required)");
  cmd->add_option("--params", o->params,
                  "Stability params file, the car's ROS 2 layout (required); vehicle constants "
                  "from its optional vehicle.* and tires.* keys");
  cmd->add_option("--compare", o->compare,
                  "Second params file: print where its outputs differ from --params");
  cmd->add_option("-o,--output", o->out,
                  "Write one output row per log row to this CSV (with --compare: the outputs "
                  "of --params)");
  cmd->add_flag("--release-compat", o->release_compat,
                "Behave like the released node: long_fx ignored (TC never activates)");
  cmd->add_option("--node", o->node, "Node key in the params files")->capture_default_str();
  cmd->add_flag("--columns", o->columns,
                "Print the tables of the log's input columns and the output columns (Markdown) "
                "and exit");
  cmd->callback([o] { SetExitCode(RunReplay(*o)); });
}

const CommandRegistrar kRegistrar(60, &AddReplay);

}  // namespace
}  // namespace scw::cli
