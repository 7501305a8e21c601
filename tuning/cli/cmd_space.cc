// scw space print|show — the tuner's search spaces.
#include <iostream>
#include <memory>

#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/optim/space.h"

namespace scw::cli {
namespace {

struct SpaceOptions {
  std::string space;
};

tuning::ParameterSpace LoadSpace(const std::string& path) {
  return path.empty() ? tuning::ParameterSpace::Default() : tuning::ParameterSpace::FromFile(path);
}

void AddSpace(CLI::App& app) {
  auto* cmd = app.add_subcommand("space", "Inspect the tuner's search spaces");
  cmd->require_subcommand(1, 1);
  auto o = std::make_shared<SpaceOptions>();

  auto* print = cmd->add_subcommand(
      "print", "Print a space as YAML (no --space: the built-in default space)");
  print->add_option("--space", o->space, "Space file (params/spaces/*.yaml)");
  print->callback([o] {
    std::cout << LoadSpace(o->space).ToYaml();
    SetExitCode(kExitOk);
  });

  auto* show = cmd->add_subcommand(
      "show", "List each dimension with its transform, bounds and the shipped value's position");
  show->add_option("--space", o->space, "Space file (params/spaces/*.yaml)");
  show->callback([o] {
    const auto space = LoadSpace(o->space);
    const auto u0 = space.Encode(params::StabilityParams{});
    const auto x0 = space.Arguments(u0);
    std::cout << "space '" << space.name() << "': " << space.size() << " dimensions\n";
    for (int i = 0; i < space.size(); ++i) {
      const auto& e = space.entries()[static_cast<std::size_t>(i)];
      std::cout << "  " << e.Label() << "  x in [" << params::FormatDouble(e.lo) << ", "
                << params::FormatDouble(e.hi) << "]"
                << (e.scale == params::Scale::kLog ? " log" : "")
                << (e.of.empty() ? "" : "  relative to " + e.of)
                << "  shipped x = " << params::FormatDouble(x0[static_cast<std::size_t>(i)])
                << '\n';
    }
    SetExitCode(kExitOk);
  });
}

const CommandRegistrar kRegistrar(40, &AddSpace);

}  // namespace
}  // namespace scw::cli
