// scw space print|show — the tuner's search spaces.
#include <iostream>
#include <memory>

#include "params/io/load.h"
#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/optim/space.h"

namespace scw::cli {
namespace {

struct SpaceOptions {
  std::string space;
  std::string base;
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
      "show",
      "List each dimension with its transform, bounds and the base value's position; warn where "
      "the base lies outside a range");
  show->add_option("--space", o->space, "Space file (params/spaces/*.yaml)");
  show->add_option("--base", o->base,
                   "Stability params file (car's ROS 2 layout; default: the shipped parameters)");
  show->callback([o] {
    const auto space = LoadSpace(o->space);
    const params::StabilityParams base =
        o->base.empty()
            ? params::StabilityParams{}
            : params::LoadRosFile<params::StabilityParams>(o->base, params::kStabilityNodeKey);
    const std::string who = o->base.empty() ? "shipped" : "base";
    const auto u0 = space.Encode(base);
    const auto x0 = space.Arguments(u0);
    const auto mismatches = space.BaseMismatches(base);
    std::cout << "space '" << space.name() << "': " << space.size() << " dimensions\n";
    for (int i = 0; i < space.size(); ++i) {
      const auto& e = space.entries()[static_cast<std::size_t>(i)];
      double x = x0[static_cast<std::size_t>(i)];
      std::string outside;
      for (const auto& m : mismatches)
        if (m.index == i) {
          x = m.x_base;  // not the clamped value
          outside = "  OUTSIDE the range (see the warning)";
        }
      std::cout << "  " << e.Label() << "  x in [" << params::FormatDouble(e.lo) << ", "
                << params::FormatDouble(e.hi) << "]"
                << (e.scale == params::Scale::kLog ? " log" : "")
                << (e.of.empty() ? "" : "  relative to " + e.of) << "  " << who
                << " x = " << params::FormatDouble(x) << outside << '\n';
    }
    for (const auto& m : mismatches)
      std::cerr << "warning: " << m.label << ": " << m.message
                << (m.representable
                        ? "; scw tune grows the range to [" + params::FormatNumber(m.grown_lo) +
                              ", " + params::FormatNumber(m.grown_hi) +
                              "] (or refuses with --base-outside refuse)"
                        : "; scw tune refuses this base (no range can represent it)")
                << '\n';
    SetExitCode(kExitOk);
  });
}

const CommandRegistrar kRegistrar(40, &AddSpace);

}  // namespace
}  // namespace scw::cli
