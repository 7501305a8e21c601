// Running the built `scw` program from a test as a user runs it from a shell: stdout and stderr go
// to files (not a terminal), so the program behaves as in a script; the result holds the exit code
// and both texts. Shared by the command-line tests (test/tuning/cli). Header-only.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace scw::test {

/// The whole content of a file, "" when it cannot be read.
inline std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// How a run of a program ended and what it printed.
struct CliResult {
  int code = -1;  ///< the exit code; -1 when the program did not exit (a signal)
  std::string out, err;
  std::string all() const { return out + err; }
};

/// Runs `program args` through the shell with stdout and stderr into `dir`/stdout.txt and
/// `dir`/stderr.txt (`dir` must exist; the files are overwritten by the next run).
inline CliResult RunCli(const std::string& program, const std::string& args,
                        const std::filesystem::path& dir) {
  const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
  const int rc = std::system((program + " " + args + " > " + out + " 2> " + err).c_str());
  CliResult r;
  r.code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = Slurp(out);
  r.err = Slurp(err);
  return r;
}

}  // namespace scw::test
