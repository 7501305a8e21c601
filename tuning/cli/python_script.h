// Runs a Python script embedded in the scw binary (the figures the CLI draws with matplotlib:
// `scw maneuver --plot`). The libraries never start a process to draw; the CLI does, here.
//
// The script is sent on stdin (`PYTHON - ARGS...`); it must exit 3 when matplotlib is missing and
// print its reason for any other failure on its last line. Interpreter: the environment variable
// SCW_PYTHON, else `python3` from PATH and, if that one lacks matplotlib, /usr/bin/python3.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace scw::cli {

/// Exit code a plot script uses when matplotlib cannot be imported.
inline constexpr int kScriptNoMatplotlib = 3;

/// Runs `script` with `args`. Returns false with a one-line reason in `*message` when no
/// interpreter with matplotlib is found or the script fails; never throws. Blocks until it ends.
bool RunPythonScript(std::string_view script, const std::vector<std::string>& args,
                     std::string* message);

}  // namespace scw::cli
