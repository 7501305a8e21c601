#include "tuning/cli/options.h"

#include <iostream>
#include <thread>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <system_error>

#include "params/io/suggest.h"
#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::cli {
namespace {

std::string Quoted(const std::string& s) { return "'" + s + "'"; }

/// Decimal whole number with an optional sign, nothing else ("0x10", "1e3", "1.0" are not).
bool ParseWhole(const std::string& text, long long* out, bool* overflow) {
  *overflow = false;
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, *out);
  if (r.ec == std::errc::result_out_of_range && r.ptr == e) *overflow = true;
  return r.ec == std::errc() && r.ptr == e;
}

bool ParseFinite(const std::string& text, double* out) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e && std::isfinite(*out);
}

std::string Range(const std::string& lo, const std::string& hi) {
  return "[" + lo + ", " + hi + "]";
}

}  // namespace

CLI::Option* WholeNumberIn(CLI::Option* option, long long lo, long long hi) {
  const std::string range = Range(std::to_string(lo), std::to_string(hi));
  return option->type_name("INT in " + range)
      ->check(CLI::Validator(
          [lo, hi, range](std::string& text) -> std::string {
            long long v = 0;
            bool overflow = false;
            if (!ParseWhole(text, &v, &overflow)) {
              double x = 0.0;
              if (overflow) return text + " is outside " + range;
              return Quoted(text) +
                     (ParseFinite(text, &x) ? " is not a whole number" : " is not a number");
            }
            if (v < lo || v > hi) return text + " is outside " + range;
            text = std::to_string(v);  // CLI11 would read a leading 0 as octal
            return "";
          },
          ""));
}

CLI::Option* NumberIn(CLI::Option* option, double lo, double hi) {
  const std::string range = Range(params::FormatNumber(lo), params::FormatNumber(hi));
  return option->type_name("NUMBER in " + range)
      ->check(CLI::Validator(
          [lo, hi, range](std::string& text) -> std::string {
            double v = 0.0;
            if (!ParseFinite(text, &v)) return Quoted(text) + " is not a number";
            if (v < lo || v > hi) return text + " is outside " + range;
            return "";
          },
          ""));
}

CLI::Validator FiniteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        return ParseFinite(text, &v) ? "" : Quoted(text) + " is not a number";
      },
      "");
}

CLI::Option* SeedOption(CLI::Option* option) {
  return option->type_name("UINT")->check(CLI::Validator(
      [](std::string& text) -> std::string {
        const char* b = text.data();
        const char* e = b + text.size();
        if (b != e && *b == '+') ++b;
        std::uint64_t v = 0;
        const auto r = std::from_chars(b, e, v);
        if (b != e && r.ptr == e && r.ec == std::errc()) {
          text = std::to_string(v);  // CLI11 would read a leading 0 as octal
          return "";
        }
        if (b != e && *b == '-') {
          long long neg = 0;
          bool overflow = false;
          if (ParseWhole(text, &neg, &overflow) || overflow)
            return text + " is negative: a seed is a whole number from 0 to " +
                   std::to_string(std::numeric_limits<std::uint64_t>::max());
        }
        if (r.ec == std::errc::result_out_of_range && r.ptr == e)
          return text + " is too large: a seed is a whole number from 0 to " +
                 std::to_string(std::numeric_limits<std::uint64_t>::max());
        double x = 0.0;
        return Quoted(text) +
               (ParseFinite(text, &x) ? " is not a whole number" : " is not a number");
      },
      ""));
}

void PrintBadInput(std::ostream& out, const std::vector<std::string>& lines,
                   const std::string& hint) {
  out << "error: invalid input\n";
  for (const auto& l : lines) out << l << '\n';
  if (!hint.empty()) out << hint << '\n';
  out.flush();
}

std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  if (word.empty()) return "";
  const std::size_t limit = word.size() <= 4 ? 1 : 2;
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::size_t d = params::EditDistance(word, c, best_d);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  if (!best.empty()) return best;
  // An unambiguous abbreviation of 3+ characters ("sim" for simulate).
  if (word.size() >= 3) {
    std::string only;
    int n = 0;
    for (const auto& c : candidates)
      if (c.rfind(word, 0) == 0) {
        only = c;
        ++n;
      }
    if (n == 1) return only;
  }
  return "";
}

void RefuseRepeatedKeys(const std::string& command, const std::string& option,
                        const std::vector<std::string>& items) {
  std::vector<Problem> problems;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string key = items[i].substr(0, items[i].find('='));
    for (std::size_t j = 0; j < i; ++j)
      if (items[j].substr(0, items[j].find('=')) == key) {
        problems.push_back({option, key + " is given twice (" + items[j] + ", " + items[i] +
                                        "); set each key once"});
        break;
      }
  }
  if (!problems.empty()) throw ConfigError(command, problems);
}

void RefuseSharedOutputs(const std::string& command,
                         const std::vector<std::pair<std::string, std::string>>& outputs) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, fs::path>> seen;  // option, resolved path
  std::vector<Problem> problems;
  for (const auto& [option, path] : outputs) {
    if (path.empty() || path == "-") continue;
    // Follow symlinks (also dangling ones: the output will be written through them) to the
    // final target, then normalise the folders on the way.
    std::error_code ec;
    fs::path resolved = fs::absolute(path, ec);
    for (int hops = 0; hops < 40 && fs::is_symlink(resolved, ec); ++hops) {
      const fs::path to = fs::read_symlink(resolved, ec);
      if (ec) break;
      resolved = to.is_absolute() ? to : resolved.parent_path() / to;
    }
    const fs::path canonical = fs::weakly_canonical(resolved, ec);
    resolved = ec ? resolved.lexically_normal() : canonical;
    for (const auto& [other, where] : seen)
      if (where == resolved) {
        problems.push_back(
            {option, "writes the same file as " + other + " (" + path +
                         (resolved.string() != path ? " = " + resolved.string() : std::string()) +
                         "); give each output its own path"});
        break;
      }
    seen.emplace_back(option, resolved);
  }
  if (!problems.empty()) throw ConfigError(command, problems);
}

void NoteThreads(const std::string& command, int threads) {
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores == 0 || threads <= static_cast<int>(cores)) return;
  std::cerr << command << ": note: --threads " << threads << " is more than this machine's "
            << cores << " cores; the extra threads share them (the results are the same, the run "
            << "is not faster)\n";
}

}  // namespace scw::cli
