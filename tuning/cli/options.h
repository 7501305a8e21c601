// Shared option vocabulary of the scw commands: number checks with plain messages, hidden aliases
// for old option spellings, and the one format of bad-input messages.
//
// Bad input (exit 2) is always reported as
//
//   error: invalid input
//   <source>: <key>: <rule>          one line per problem, e.g.
//   scw tune: --max-evals: 'abc' is not a number
//   stability.yml: ESC.kp_psi_dot: -1 is below the lower bound 0 (line 97)
//
// where <source> is the file, or the command for command-line arguments.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace scw::cli {

/// The option takes whole numbers in [lo, hi] (decimal digits, optional sign): "'abc' is not a
/// number", "'1.5' is not a whole number", "2000 is outside [0, 1024]".
CLI::Option* WholeNumberIn(CLI::Option* option, long long lo, long long hi);
/// The option takes finite numbers in [lo, hi] ("'abc' is not a number", "... is outside ...").
CLI::Option* NumberIn(CLI::Option* option, double lo, double hi);
/// Each value is a finite number ("'abc' is not a number"); for list options.
CLI::Validator FiniteNumber();
/// A seed: a whole number from 0 to 2^64 - 1 (a negative seed is refused, not wrapped around).
CLI::Option* SeedOption(CLI::Option* option);

/// A note on stderr when `threads` asks for more worker threads than the machine has cores (the
/// results are the same; the extra threads only share the cores). `command` names the command.
void NoteThreads(const std::string& command, int threads);

/// Adds `name` (e.g. "--out") as a hidden alias of an option bound to `value`: it works as
/// before but is not listed in --help.
template <class T>
CLI::Option* AddHiddenAlias(CLI::App* cmd, const std::string& name, T& value) {
  return cmd->add_option(name, value, "(old spelling)")->group("");
}

/// Refuses (scw::ConfigError, exit 2) `key=value` items of one option that set a key twice, as a
/// key given twice in a file is refused: "scw simulate: --set: laps is given twice (laps=2,
/// laps=3); set each key once". `command` e.g. "scw simulate", `option` e.g. "--set".
void RefuseRepeatedKeys(const std::string& command, const std::string& option,
                        const std::vector<std::string>& items);

/// Refuses (scw::ConfigError, exit 2) outputs of one command that name the same file, after
/// following symbolic links (one output would silently replace the other): `outputs` are (option,
/// path) pairs; empty paths and `-` (standard output) are skipped.
void RefuseSharedOutputs(const std::string& command,
                         const std::vector<std::pair<std::string, std::string>>& outputs);

/// Writes the bad-input block: "error: invalid input" and the problem lines (each already
/// `<source>: <key>: <rule>`), then the hint (if any) on its own line.
void PrintBadInput(std::ostream& out, const std::vector<std::string>& lines,
                   const std::string& hint = "");

/// The closest of `candidates` to `word` when it is a likely typo (edit distance with
/// transpositions, at most 1 for short words, 2 from 5 characters on), else "".
std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace scw::cli
