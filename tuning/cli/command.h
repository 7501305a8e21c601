// Sub-command registry of the `scw` program. Each command lives in its own cmd_<name>.cc and
// registers itself with a static `CommandRegistrar`, so commands can be added without editing a
// central list.
//
// Exit codes (all commands): 0 success, 1 a run failed (simulation aborted, optimisation error,
// I/O failure while writing), 2 bad input (unreadable or invalid file, bad arguments), 130
// interrupted by Ctrl-C (scw tune: after writing the outputs of the best set so far).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace scw::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadInput = 2;
/// Stopped by Ctrl-C (128 + SIGINT, as a shell reports it) after writing what was done so far.
inline constexpr int kExitInterrupted = 130;

/// The exit codes, as every --help lists them (the footer of `scw --help` and of each command).
inline constexpr const char* kExitCodesHelp =
    "Exit codes: 0 success, 1 a run failed (simulation aborted, optimisation error, a file\n"
    "could not be written; params diff: the files differ), 2 bad input (unreadable or invalid\n"
    "file, bad arguments), 130 interrupted (Ctrl-C; scw tune writes the best set so far first).";

/// Adds one sub-command (with its options and callback) to the top-level app.
using AddCommandFn = void (*)(CLI::App& app);

struct CommandRegistrar {
  /// `order` sorts the commands in `scw --help`.
  CommandRegistrar(int order, AddCommandFn add);
};

/// Called by a command's callback to set the process exit code.
void SetExitCode(int code);

/// The process's command line (for run manifests).
const std::vector<std::string>& CommandLine();

}  // namespace scw::cli
