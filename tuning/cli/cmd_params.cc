// scw params import|export|validate|check|diff|docs — the car's ROS 2 parameter files.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "params/io/atomic_file.h"
#include "params/io/docs.h"
#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/stability_lint.h"
#include "params/io/write.h"
#include "params/schema/cost_params.h"
#include "params/schema/scenario_params.h"
#include "params/schema/stability_params.h"
#include "params/schema/track_params.h"
#include "params/schema/tracking_params.h"
#include "params/schema/vehicle_params.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/optim/space.h"
#include "tuning/sim/scenario_set.h"

namespace scw::cli {
namespace {

using params::LoadOptions;
using params::LoadReport;

struct ParamsOptions {
  std::string kind = "stability";
  std::string file, file_b, out, base, node;
  bool overrides_only = false;
};

std::string DefaultNode(const std::string& kind) {
  return kind == "tracking" ? params::kTrackingNodeKey : params::kStabilityNodeKey;
}

template <class P>
P LoadCar(const std::string& path, const std::string& node, bool lenient, LoadReport* rep) {
  LoadOptions opt;
  opt.layout = params::Layout::kRos2;
  opt.node_key = node;
  opt.lenient = lenient;
  return params::LoadFromFile<P>(path, opt, rep);
}

void PrintNotes(const std::string& file, const LoadReport& rep) {
  for (const auto& n : rep.notes)
    std::cerr << file << ": note: " << n.path << ": " << n.message << '\n';
}

/// Runs the rcl-rule checker on text we are about to write; refuses to write a file the car's node
/// would not load.
template <class P>
void CheckBeforeWrite(const std::string& text, const std::string& node, bool complete,
                      const std::string& out) {
  params::CheckOptions co;
  co.node_key = node;
  co.expect_complete = complete;
  const auto rep = params::CheckRosParamsText(text, params::DeclaredParams<P>(), co);
  if (!rep.ok())
    throw std::runtime_error("internal error: the export to " + out +
                             " fails the ROS 2 params check:\n" + rep.Format(out));
}

template <class P>
int Import(const ParamsOptions& o) {
  LoadReport rep;
  const P p = LoadCar<P>(o.file, o.node, /*lenient=*/true, &rep);
  PrintNotes(o.file, rep);
  const std::string node = o.node.empty() ? DefaultNode(o.kind) : o.node;
  const std::string text =
      params::ToRosYaml(p, node, rep.present, "Imported by scw from " + o.file);
  CheckBeforeWrite<P>(text, node, true, o.out);
  io::WriteFileAtomic(o.out, text);
  std::cerr << "imported " << rep.present.size() << " keys from " << o.file << " into " << o.out
            << " (" << rep.notes.size() << " note(s))\n";
  return kExitOk;
}

template <class P>
int Export(const ParamsOptions& o) {
  LoadReport rep;
  const P p = LoadCar<P>(o.file, "", /*lenient=*/false, &rep);
  const std::string node = o.node.empty() ? DefaultNode(o.kind) : o.node;
  std::string text;
  if (!o.overrides_only && !o.base.empty())
    throw ConfigError("scw params export", "--base",
                      "is used only with --overrides-only (without it the whole file is "
                      "exported and BASE would be ignored); add --overrides-only or drop --base");
  if (o.overrides_only) {
    if (o.base.empty()) throw ConfigError("", "--base", "--overrides-only needs --base BASE");
    const P base = LoadCar<P>(o.base, "", /*lenient=*/true, nullptr);
    text = params::ToRosOverrides(
        p, base, node,
        "Overrides of " + o.file + " against " + o.base + "; load after the base file");
  } else {
    text = params::ToRosYaml(p, node, rep.present, "Exported by scw from " + o.file);
  }
  CheckBeforeWrite<P>(text, node, !o.overrides_only, o.out);
  io::WriteFileAtomic(o.out, text);
  std::cerr << "wrote " << o.out << '\n';
  return kExitOk;
}

template <class P>
int Validate(const ParamsOptions& o) {
  LoadReport rep;
  LoadCar<P>(o.file, o.node.empty() ? DefaultNode(o.kind) : o.node, false, &rep);
  std::cout << o.file << ": ok (" << rep.present.size() << " keys)\n";
  return kExitOk;
}

template <class P>
int Check(const ParamsOptions& o) {
  const std::string node = o.node.empty() ? DefaultNode(o.kind) : o.node;
  const std::string text = params::ReadTextFile(o.file);
  params::CheckOptions co;
  co.node_key = node;
  co.expect_complete = !o.overrides_only;
  auto rep = params::CheckRosParamsText(text, params::DeclaredParams<P>(), co);
  if (rep.ok()) {
    // Values: bounds and rules of the schema (the node itself validates almost nothing).
    try {
      LoadReport lr;
      LoadOptions lo;
      lo.layout = params::Layout::kRos2;
      lo.node_key = node;
      lo.lenient = true;
      const P p = params::LoadFromText<P>(text, o.file, lo, &lr);
      if constexpr (std::is_same_v<P, params::StabilityParams>)
        for (const auto& w : params::LintStability(p))
          rep.findings.push_back({false, w.path, w.message, 0});
    } catch (const ConfigError& e) {
      if (!o.overrides_only)
        for (const auto& pr : e.problems()) rep.findings.push_back({true, pr.path, pr.message, 0});
    }
  }
  // The format of every bad-input message (as `params validate`): errors under
  // "error: invalid input" as `file: key: rule (line N)`; warnings as `warning: file: ...`.
  std::vector<std::string> errors;
  for (const auto& f : rep.findings) {
    std::string line = o.file + ": " + (f.key.empty() ? "" : f.key + ": ") + f.message;
    if (f.line > 0 && f.message.find("(line ") == std::string::npos)
      line += " (line " + std::to_string(f.line) + ")";
    if (f.error)
      errors.push_back(line);
    else
      std::cerr << "warning: " << line << '\n';
  }
  if (!errors.empty()) PrintBadInput(std::cerr, errors);
  std::cout << o.file << ": " << rep.errors() << " error(s), " << rep.warnings() << " warning(s)\n";
  return rep.ok() ? kExitOk : kExitBadInput;
}

template <class P>
int Diff(const ParamsOptions& o) {
  // Both files as the car's node reads them (a duplicate: the last value; an unknown key:
  // ignored), with a note per such problem, so that "0 key(s) differ" never hides a key that the
  // node ignores or a value given twice. Invalid files (types, bounds, missing keys): exit 2.
  LoadReport rep_a, rep_b;
  const P a = LoadCar<P>(o.file, "", true, &rep_a);
  const P b = LoadCar<P>(o.file_b, "", true, &rep_b);
  PrintNotes(o.file, rep_a);
  PrintNotes(o.file_b, rep_b);
  const std::size_t notes = rep_a.notes.size() + rep_b.notes.size();
  std::vector<std::tuple<std::string, std::string, std::string>> va, vb;
  params::ForEachField(a, [&](const std::string& path, const auto& v, const params::Meta& m) {
    va.emplace_back(path, params::detail::RenderValue(v), std::string(m.unit));
  });
  params::ForEachField(b, [&](const std::string& path, const auto& v, const params::Meta& m) {
    vb.emplace_back(path, params::detail::RenderValue(v), std::string(m.unit));
  });
  int changed = 0;
  for (std::size_t i = 0; i < va.size(); ++i) {
    if (std::get<1>(va[i]) == std::get<1>(vb[i])) continue;
    ++changed;
    std::cout << std::get<0>(va[i]) << ": " << std::get<1>(va[i]) << " -> " << std::get<1>(vb[i])
              << " [" << std::get<2>(va[i]) << "]\n";
  }
  std::cerr << changed << " key(s) differ";
  if (notes > 0)
    std::cerr << "; " << notes
              << " note(s) above: keys the car's node ignores (unknown) or reads only once "
                 "(given twice) are not compared as written";
  std::cerr << '\n';
  constexpr int kExitDiffer = 1;  // as diff(1): 0 same, 1 different, 2 trouble
  return changed == 0 ? kExitOk : kExitDiffer;
}

template <class P>
int Init(const ParamsOptions& o) {
  const std::string node = o.node.empty() ? DefaultNode(o.kind) : o.node;
  const std::string text = params::ToRosYaml(
      P{}, node, {},
      "Built-in defaults of scw: the values the car runs (shipped params file; optional node keys\n"
      "at the node's code defaults are omitted). Regenerate: scw params init --kind " +
          o.kind + " -o FILE");
  CheckBeforeWrite<P>(text, node, true, o.out);
  io::WriteFileAtomic(o.out, text);
  std::cerr << "wrote " << o.out << '\n';
  return kExitOk;
}

template <class P>
int WriteDocs(const ParamsOptions& o, const std::string& title) {
  const std::string text = "# " + title + "\n\nGenerated by `scw params docs --kind " + o.kind +
                           "` from the schema; do not edit by hand.\n\n" +
                           params::MarkdownTable<P>();
  if (o.out.empty())
    std::cout << text;
  else
    io::WriteFileAtomic(o.out, text);
  return kExitOk;
}

/// Reference tables of every schema, not only the car's two node files.
int Docs(const ParamsOptions& o) {
  if (o.kind == "tracking")
    return WriteDocs<params::TrackingParams>(
        o, "Tracking controller parameters (node `" + DefaultNode(o.kind) + "`)");
  if (o.kind == "scenario")
    return WriteDocs<params::ScenarioParams>(o, "Scenario files (params/scenarios/*.yaml)");
  if (o.kind == "vehicle")
    return WriteDocs<params::VehicleParams>(o, "Vehicle files (params/vehicles/*.yaml)");
  if (o.kind == "track")
    return WriteDocs<params::TrackParams>(o, "Piecewise track files (params/tracks/*.yaml)");
  if (o.kind == "cost")
    return WriteDocs<params::CostWeights>(o, "Tuning cost weights (`cost:` of a scenario set)");
  if (o.kind == "scenario-set")
    return WriteDocs<tuning::ScenarioSetFile>(
        o, "Scenario-set files (params/scenarios/*_set.yaml; scw tune --scenarios)");
  if (o.kind == "space")
    return WriteDocs<tuning::SpaceFile>(
        o, "Search-space files (params/spaces/*.yaml; scw tune --space)");
  return WriteDocs<params::StabilityParams>(
      o, "Stability controller parameters (node `" + DefaultNode(o.kind) + "`)");
}

template <template <class> class Fn>
int Dispatch(const ParamsOptions& o) {
  if (o.kind == "tracking") return Fn<params::TrackingParams>::Run(o);
  return Fn<params::StabilityParams>::Run(o);
}

#define SCW_PARAMS_ACTION(Name)                                   \
  template <class P>                                              \
  struct Name##Action {                                           \
    static int Run(const ParamsOptions& o) { return Name<P>(o); } \
  };
SCW_PARAMS_ACTION(Import)
SCW_PARAMS_ACTION(Export)
SCW_PARAMS_ACTION(Validate)
SCW_PARAMS_ACTION(Check)
SCW_PARAMS_ACTION(Diff)
SCW_PARAMS_ACTION(Init)
#undef SCW_PARAMS_ACTION

/// The node key each --kind writes when --node is not given (DefaultNode), for the help texts.
std::string DefaultNodes() {
  return std::string(params::kStabilityNodeKey) + ", or " + params::kTrackingNodeKey +
         " with --kind tracking";
}

void AddKindOption(CLI::App* sub, ParamsOptions* o) {
  sub->add_option("--kind", o->kind, "Parameter set: stability (default) or tracking")
      ->check(CLI::IsMember({"stability", "tracking"}));
}

void AddParams(CLI::App& app) {
  auto* cmd = app.add_subcommand("params",
                                 "Read, check, compare and export the car's ROS 2 "
                                 "parameter files");
  cmd->require_subcommand(1, 1);
  auto o = std::make_shared<ParamsOptions>();

  auto* imp =
      cmd->add_subcommand("import",
                          "Read a params file from the car, report duplicate/unknown keys and type "
                          "mismatches, write a normalized file");
  imp->add_option("FILE", o->file, "Params file from the car")->required();
  imp->add_option("-o,--output", o->out, "Normalized output file")->required();
  imp->add_option("--node", o->node, "Node key to read/write (default: the file's only node)");
  AddKindOption(imp, o.get());
  imp->callback([o] { SetExitCode(Dispatch<ImportAction>(*o)); });

  auto* exp = cmd->add_subcommand(
      "export", "Write a params file the car's node loads unchanged (full or overrides-only)");
  exp->add_option("FILE", o->file, "Parameter file (ROS 2 layout)")->required();
  exp->add_option("-o,--output", o->out, "Output file")->required();
  exp->add_flag("--overrides-only", o->overrides_only,
                "Only the keys that differ from --base (load after the base file)");
  exp->add_option("--base", o->base, "Base file for --overrides-only");
  exp->add_option("--node", o->node, "Node key written (default: " + DefaultNodes() + ")");
  AddKindOption(exp, o.get());
  exp->callback([o] { SetExitCode(Dispatch<ExportAction>(*o)); });

  auto* val = cmd->add_subcommand("validate",
                                  "Strictly validate a params file (exit 2 listing every problem)");
  val->add_option("FILE", o->file, "Params file")->required();
  val->add_option("--node", o->node, "Expected node key");
  AddKindOption(val, o.get());
  val->callback([o] { SetExitCode(Dispatch<ValidateAction>(*o)); });

  auto* chk =
      cmd->add_subcommand("check",
                          "Apply the ROS 2 parser's typing rules and the node's declarations, plus "
                          "engineering warnings (exit 2 on errors)");
  chk->add_option("FILE", o->file, "Params file")->required();
  chk->add_option("--node", o->node, "Expected node key");
  chk->add_flag("--overrides", o->overrides_only, "The file is an overrides-only file");
  AddKindOption(chk, o.get());
  chk->callback([o] { SetExitCode(Dispatch<CheckAction>(*o)); });

  auto* dif = cmd->add_subcommand(
      "diff",
      "Print the keys whose values differ, with units (exit 0: same values, 1: values differ, "
      "2: a file is unreadable or invalid; as diff)");
  dif->add_option("A", o->file, "First params file")->required();
  dif->add_option("B", o->file_b, "Second params file")->required();
  AddKindOption(dif, o.get());
  dif->callback([o] { SetExitCode(Dispatch<DiffAction>(*o)); });

  auto* ini = cmd->add_subcommand("init", "Write the built-in default parameter file");
  ini->add_option("-o,--output", o->out, "Output file")->required();
  ini->add_option("--node", o->node, "Node key written (default: " + DefaultNodes() + ")");
  AddKindOption(ini, o.get());
  ini->callback([o] { SetExitCode(Dispatch<InitAction>(*o)); });

  auto* doc = cmd->add_subcommand("docs", "Print the parameter reference table (Markdown)");
  doc->add_option("-o,--output", o->out, "Write to a file instead of stdout");
  doc->add_option("--kind", o->kind,
                  "stability (default), tracking, scenario, vehicle, track, cost, scenario-set, "
                  "space")
      ->check(CLI::IsMember({"stability", "tracking", "scenario", "vehicle", "track", "cost",
                             "scenario-set", "space"}));
  doc->callback([o] { SetExitCode(Docs(*o)); });
}

const CommandRegistrar kRegistrar(10, &AddParams);

}  // namespace
}  // namespace scw::cli
