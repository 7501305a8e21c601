#include <algorithm>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "params/io/atomic_file.h"
#include "params/schema/field.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/cli/revision.h"  // generated: SCW_GIT_REVISION
#include "tuning/exec/mpi_backend.h"
#include "tuning/optim/evaluator.h"
#include "tuning/sweep/sweep.h"

namespace scw::cli {
namespace {
std::vector<std::pair<int, AddCommandFn>>& Registry() {
  static std::vector<std::pair<int, AddCommandFn>> commands;
  return commands;
}
int g_exit_code = kExitOk;
std::vector<std::string> g_command_line;

std::vector<CLI::App*> Subcommands(CLI::App* app) {
  return app->get_subcommands([](CLI::App*) { return true; });
}

std::vector<std::string> SubcommandNames(CLI::App* app) {
  std::vector<std::string> names;
  for (auto* s : Subcommands(app)) names.push_back(s->get_name());
  return names;
}

std::string Join(const std::vector<std::string>& items, const std::string& sep) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : sep) + s;
  return out;
}

/// The commands named on the command line, outermost first (the words before the first option).
/// Stops at the first word that is not a command of a group: `unknown` is set to it.
struct CommandWalk {
  std::vector<CLI::App*> path;  ///< path.front() = the program
  std::string unknown;          ///< a word that names no command of path.back()
  bool bare = false;            ///< path.back() is a group and nothing follows
};

CommandWalk Walk(CLI::App* app, int argc, char** argv) {
  CommandWalk w;
  w.path.push_back(app);
  int i = 1;
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    CLI::App* node = w.path.back();
    const auto subs = Subcommands(node);
    if (subs.empty() || (!a.empty() && a[0] == '-')) break;
    const auto it =
        std::find_if(subs.begin(), subs.end(), [&](CLI::App* s) { return s->check_name(a); });
    if (it == subs.end()) {
      w.unknown = a;
      return w;
    }
    w.path.push_back(*it);
  }
  w.bare = i == argc && !Subcommands(w.path.back()).empty();
  return w;
}

std::string CommandName(const CommandWalk& w) {
  std::string name = "scw";
  for (std::size_t k = 1; k < w.path.size(); ++k) name += " " + w.path[k]->get_name();
  return name;
}

std::vector<std::string> LongOptionNames(const CLI::App* app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app->get_options())
    if (!o->get_group().empty())
      for (const auto& l : o->get_lnames()) names.push_back("--" + l);
  return names;
}

/// CLI11's message, said the way the other errors are said (`--key: rule`, lower case).
std::vector<std::string> ArgumentProblems(const CLI::ParseError& e, const CommandWalk& w) {
  const std::string cmd = CommandName(w);
  std::string what = e.what();
  std::vector<std::string> out;
  for (const char* prefix :
       {"The following argument was not expected: ", "The following arguments were not expected: "})
    if (what.rfind(prefix, 0) == 0) {
      // CLI11 lists them last first.
      const std::string rest = what.substr(std::string(prefix).size());
      std::vector<std::string> args;
      std::size_t at = 0;
      while (at < rest.size()) {
        const std::size_t sp = rest.find(' ', at);
        const std::string arg = rest.substr(at, sp == std::string::npos ? sp : sp - at);
        at = sp == std::string::npos ? rest.size() : sp + 1;
        if (!arg.empty()) args.insert(args.begin(), arg);
      }
      for (const auto& arg : args)
        if (arg[0] == '-') {
          const std::string name = arg.substr(0, arg.find('='));
          const std::string hint = DidYouMean(name, LongOptionNames(w.path.back()));
          out.push_back(cmd + ": unknown option '" + name + "'" +
                        (hint.empty() ? "" : " (did you mean " + hint + "?)"));
        }
      // Words after an unknown option are most likely its values: name only the option then.
      if (out.empty())
        for (const auto& arg : args) out.push_back(cmd + ": unexpected argument '" + arg + "'");
      return out;
    }
  if (what == "A subcommand is required")
    return {cmd + ": a command is required: " + Join(SubcommandNames(w.path.back()), ", ")};
  const std::string conv = "Could not convert: ";
  if (what.rfind(conv, 0) == 0) {
    const std::string rest = what.substr(conv.size());
    const auto eq = rest.find(" = ");
    if (eq != std::string::npos)
      return {cmd + ": " + rest.substr(0, eq) + ": cannot read '" + rest.substr(eq + 3) + "'"};
  }
  if (!what.empty() && what[0] >= 'A' && what[0] <= 'Z' && what.size() > 1 && what[1] >= 'a' &&
      what[1] <= 'z')
    what[0] = static_cast<char>(what[0] - 'A' + 'a');
  return {cmd + ": " + what};
}

/// Every option value on the command line that its option's checks refuse, as problem lines
/// ("scw tune: --seed: -1 is negative: ..."), so that a command line with several bad values is
/// reported whole, not one value per attempt (CLI11 stops at the first).
std::vector<std::string> ValueProblems(const CommandWalk& w, int argc, char** argv) {
  std::vector<std::string> out;
  CLI::App* cmd = w.path.back();
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.size() < 2 || arg[0] != '-' || arg == "--") continue;
    const auto eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    CLI::Option* opt = cmd->get_option_no_throw(name);
    if (opt == nullptr || opt->get_items_expected_max() == 0) continue;  // unknown, or a flag
    std::string value;
    if (eq != std::string::npos)
      value = arg.substr(eq + 1);
    else if (i + 1 < argc)
      value = argv[++i];
    else
      continue;
    for (int k = 0;; ++k) {
      CLI::Validator* v = nullptr;
      try {
        v = opt->get_validator(k);
      } catch (const CLI::OptionNotFound&) {
        break;
      }
      std::string text = value;
      const std::string problem = (*v)(text);
      if (!problem.empty()) {
        out.push_back(CommandName(w) + ": " + name + ": " + problem);
        break;
      }
    }
  }
  return out;
}

/// "cannot create directories /x/y: Permission denied" from libstdc++'s
/// "filesystem error: cannot create directories: Permission denied [/x/y]".
std::string FilesystemMessage(const std::filesystem::filesystem_error& e) {
  std::string what = e.what();
  const std::string prefix = "filesystem error: ";
  if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
  const std::string reason = e.code().message();
  const auto at = what.find(": " + reason);
  std::string op = at == std::string::npos ? what.substr(0, what.find(':')) : what.substr(0, at);
  std::string paths = e.path1().string();
  if (!e.path2().empty()) paths += " and " + e.path2().string();
  return op + (paths.empty() ? "" : " " + paths) + ": " + reason;
}

}  // namespace

const std::vector<std::string>& CommandLine() { return g_command_line; }

CommandRegistrar::CommandRegistrar(int order, AddCommandFn add) {
  Registry().emplace_back(order, add);
}

void SetExitCode(int code) { g_exit_code = code; }

}  // namespace scw::cli

namespace {

int RunCommand(int argc, char** argv) {
  using namespace scw::cli;
  namespace mpi = scw::tuning::exec::mpi;
  g_command_line.assign(argv, argv + argc);
  CLI::App app{
      "scw - stability-control workspace: design, tune and export the stability control\n"
      "(ESC, ABS/TC slip control, countersteer) of an autonomous race car.",
      "scw"};
  app.set_version_flag("--version",
                       std::string("scw ") + SCW_VERSION + " (git revision " + SCW_GIT_REVISION +
                           ")\nMPI: " +
                           (mpi::BuiltIn() ? "built in (" + mpi::LibraryVersion() + ")"
                                           : std::string("not built in")) +
                           "\nbuild: " +
                           (SCW_BUILD_PGO ? "profile-guided optimisation (SCW_PGO)"
                                          : "without profile-guided optimisation") +
                           (SCW_BUILD_LTO ? ", link-time optimisation (SCW_LTO)" : ""));
  app.require_subcommand(1, 1);
  app.footer(kExitCodesHelp);
  // Every option shows its default in --help (subcommands copy these option defaults).
  app.option_defaults()->always_capture_default();
  auto commands = Registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, add] : commands) add(app);
  // The exit codes in every command's --help too, after what the command says itself.
  std::function<void(CLI::App*)> add_exit_codes = [&](CLI::App* a) {
    for (CLI::App* sub : a->get_subcommands({})) {
      if (dynamic_cast<CLI::Option_group*>(sub) != nullptr) continue;  // printed with its command
      // A command without a footer of its own has inherited the program's (the exit codes).
      const std::string own = sub->get_footer();
      if (own.find(kExitCodesHelp) == std::string::npos)
        sub->footer(own.empty() ? std::string(kExitCodesHelp) : own + "\n\n" + kExitCodesHelp);
      add_exit_codes(sub);
    }
  };
  add_exit_codes(&app);

  // Command words first: an unknown one gets a suggestion, a bare group lists its commands.
  const CommandWalk walk = Walk(&app, argc, argv);
  if (!walk.unknown.empty()) {
    const std::string hint = DidYouMean(walk.unknown, SubcommandNames(walk.path.back()));
    PrintBadInput(std::cerr,
                  {CommandName(walk) + ": unknown command '" + walk.unknown + "'" +
                   (hint.empty() ? "" : " (did you mean " + hint + "?)")},
                  "commands: " + Join(SubcommandNames(walk.path.back()), ", "));
    return kExitBadInput;
  }
  if (walk.bare) {
    CommandWalk parent = walk;
    parent.path.pop_back();
    std::cout << walk.path.back()->help(parent.path.empty() ? "" : CommandName(parent));
    return kExitOk;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::vector<std::string> problems = ArgumentProblems(e, walk);
    // A refused value: report every refused value of the command line at once.
    if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
      std::vector<std::string> values = ValueProblems(walk, argc, argv);
      if (!values.empty()) problems = std::move(values);
    }
    PrintBadInput(std::cerr, problems, "run '" + CommandName(walk) + " --help' for the options");
    return kExitBadInput;
  } catch (const scw::ConfigError& e) {
    std::cerr << "error: invalid input\n" << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "error: " << FilesystemMessage(e) << '\n';
    return kExitFailed;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitFailed;
  }
  return g_exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  namespace mpi = scw::tuning::exec::mpi;
  // Ctrl-C or a kill in any command removes the temporary files of unfinished outputs (the
  // targets keep their previous content), then ends the program by that signal.
  scw::io::InstallTemporaryFileCleanup();
  // Under mpirun: rank 0 runs the command, the other ranks serve its jobs until it ends.
  mpi::Init(&argc, &argv);
  if (!mpi::StartupError().empty()) {
    if (mpi::Rank() == 0) std::cerr << "error: " << mpi::StartupError() << '\n';
    return scw::cli::kExitBadInput;
  }
  const int code = mpi::Rank() == 0
                       ? RunCommand(argc, argv)
                       : mpi::RunWorker({{"evaluate", &scw::tuning::MakeEvaluatorWorkerTask},
                                         {"sweep", &scw::tuning::sweep::MakeSweepWorkerTask}});
  mpi::Finalize();
  return code;
}
