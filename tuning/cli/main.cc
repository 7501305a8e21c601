#include <algorithm>
#include <exception>
#include <iostream>
#include <utility>
#include <vector>

#include "params/io/atomic_writer.h"
#include "params/schema/field.h"
#include "tuning/cli/command.h"

namespace scw::cli {
namespace {
std::vector<std::pair<int, AddCommandFn>>& Registry() {
  static std::vector<std::pair<int, AddCommandFn>> commands;
  return commands;
}
int g_exit_code = kExitOk;
std::vector<std::string> g_command_line;
}  // namespace

const std::vector<std::string>& CommandLine() { return g_command_line; }

CommandRegistrar::CommandRegistrar(int order, AddCommandFn add) {
  Registry().emplace_back(order, add);
}

void SetExitCode(int code) { g_exit_code = code; }

}  // namespace scw::cli

int main(int argc, char** argv) {
  using namespace scw::cli;
  // Ctrl-C or a kill in any command removes the temporary files of unfinished outputs (the
  // targets keep their previous content), then ends the program by that signal.
  scw::params::InstallTemporaryFileCleanup();
  g_command_line.assign(argv, argv + argc);
  CLI::App app{
      "scw - stability-control workspace: design, tune and export the stability control\n"
      "(ESC, ABS/TC slip control, countersteer) of an autonomous race car."};
  app.set_version_flag("--version", std::string("scw ") + SCW_VERSION);
  app.require_subcommand(1, 1);
  auto commands = Registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, add] : commands) add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  } catch (const scw::ConfigError& e) {
    std::cerr << "error: invalid input\n" << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitFailed;
  }
  return g_exit_code;
}
