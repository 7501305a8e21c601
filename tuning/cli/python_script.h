// Runs a Python script embedded in the scw binary: the figures the CLI draws with matplotlib
// (`scw maneuver --plot`, the run folder of `scw tune`). The libraries never start a process to
// draw (test/architecture/check_layers.py checks it); the CLI does, here, and only here.
//
// The script is sent on stdin (`PYTHON - ARGS...`, through a socket, so that a child that dies
// early gives EPIPE rather than SIGPIPE). Its exit codes: 0 done, 2 an input is missing or
// malformed, 3 matplotlib cannot be imported (the next interpreter is tried), anything else a
// failure. Its reason for a failure is its last output line that starts with the script's
// reason prefix (without it), else its last non-empty output line.
//
// Interpreter: PythonScriptOptions::python, else the environment variable SCW_PYTHON, else
// `python3` from PATH and, if that one lacks matplotlib or is missing (a pyenv or venv python
// first on PATH), /usr/bin/python3 (Debian's, where python3-matplotlib installs).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace scw::cli {

/// Exit code a plot script uses for a missing or malformed input (its reason is the message).
inline constexpr int kScriptBadInput = 2;
/// Exit code a plot script uses when matplotlib cannot be imported.
inline constexpr int kScriptNoMatplotlib = 3;

struct PythonScriptOptions {
  std::string python;         ///< interpreter (a name looked up in PATH, or a path); "" = default
  std::string reason_prefix;  ///< the script's prefix of its failure line ("" = none)
};

/// Runs `script` with `args`. Returns false with a one-line reason in `*message` (may be null)
/// when no interpreter is found (`no Python interpreter found (tried …)`), none has matplotlib
/// (`matplotlib is not installed for …`), an input is bad (the script's reason) or the script
/// fails; clears `*message` on success. Never throws. Blocks until the script ends.
bool RunPythonScript(std::string_view script, const std::vector<std::string>& args,
                     std::string* message, const PythonScriptOptions& options = {});

}  // namespace scw::cli
