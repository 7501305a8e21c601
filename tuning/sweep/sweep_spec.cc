#include "tuning/sweep/sweep_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "params/io/text.h"
#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::tuning::sweep {
namespace {

constexpr int kMaxAxisValues = 10000;

/// Splits at commas outside [...] (list values such as [0.8, 1.0] stay whole).
std::vector<std::string> SplitTopLevel(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  for (char c : s) {
    if (c == '[') ++depth;
    if (c == ']' && depth > 0) --depth;
    if (c == ',' && depth == 0) {
      out.push_back(std::string(io::Trim(cur)));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(std::string(io::Trim(cur)));
  return out;
}

bool ParseNumber(const std::string& text, double* out) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e && b != e && std::isfinite(*out);
}

int Decimals(const std::string& text) {
  const auto dot = text.find('.');
  return dot == std::string::npos ? 0 : static_cast<int>(text.size() - dot - 1);
}

bool HasExponent(const std::string& text) { return text.find_first_of("eE") != std::string::npos; }

/// `x` with `decimals` digits after the point, trailing zeros (and a bare point) removed.
std::string FormatFixed(double x, int decimals) {
  char buf[64];
  const auto r =
      std::to_chars(buf, buf + sizeof buf, x, std::chars_format::fixed, std::min(decimals, 17));
  std::string s(buf, r.ptr);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

bool ValidName(const std::string& name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '+' ||
           c == '-';
  });
}

}  // namespace

SweepAxis ParseVary(const std::string& arg) {
  const std::string where = "--vary " + arg;
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError(where, "", "must look like key=v1,v2,... or key=start:step:stop");
  SweepAxis axis;
  axis.key = std::string(io::Trim(arg.substr(0, eq)));
  const std::string rhs = std::string(io::Trim(arg.substr(eq + 1)));
  if (axis.key.empty() || rhs.empty())
    throw ConfigError(where, "", "must look like key=v1,v2,... or key=start:step:stop");
  if (axis.key == "config")
    throw ConfigError(where, "", "'config' names the configurations (use --config)");

  const bool maybe_range = rhs.find(',') == std::string::npos &&
                           rhs.find('[') == std::string::npos &&
                           std::count(rhs.begin(), rhs.end(), ':') == 2;
  if (maybe_range) {
    const auto c1 = rhs.find(':');
    const auto c2 = rhs.find(':', c1 + 1);
    const std::string parts[3] = {std::string(io::Trim(rhs.substr(0, c1))),
                                  std::string(io::Trim(rhs.substr(c1 + 1, c2 - c1 - 1))),
                                  std::string(io::Trim(rhs.substr(c2 + 1)))};
    double v[3];
    for (int i = 0; i < 3; ++i)
      if (!ParseNumber(parts[i], &v[i]))
        throw ConfigError(
            where, "",
            "a range start:step:stop needs three finite numbers, got '" + parts[i] + "'");
    const double start = v[0], step = v[1], stop = v[2];
    if (step == 0.0) throw ConfigError(where, "", "the step of start:step:stop must not be 0");
    const double span = (stop - start) / step;
    if (span < -1e-9)
      throw ConfigError(where, "",
                        "the step " + parts[1] + " does not lead from " + parts[0] + " to " +
                            parts[2] + " (check its sign)");
    const double n = std::floor(std::max(span, 0.0) + 1e-9) + 1.0;
    if (n > kMaxAxisValues)
      throw ConfigError(where, "",
                        "the range has more than " + std::to_string(kMaxAxisValues) + " values");
    const bool exp = HasExponent(parts[0]) || HasExponent(parts[1]) || HasExponent(parts[2]);
    const int decimals = std::max({Decimals(parts[0]), Decimals(parts[1]), Decimals(parts[2])});
    for (int i = 0; i < static_cast<int>(n); ++i) {
      const double x = start + i * step;
      axis.values.push_back(exp ? params::FormatDouble(x) : FormatFixed(x, decimals));
    }
    return axis;
  }
  axis.values = SplitTopLevel(rhs);
  for (std::size_t i = 0; i < axis.values.size(); ++i)
    if (axis.values[i].empty())
      throw ConfigError(where, "", "value " + std::to_string(i + 1) + " is empty");
  return axis;
}

SweepConfig ParseConfig(const std::string& arg) {
  const std::string where = "--config " + arg;
  const auto colon = arg.find(':');
  SweepConfig c;
  c.name = std::string(io::Trim(arg.substr(0, colon)));
  if (!ValidName(c.name))
    throw ConfigError(where, "",
                      "must look like name:key=v,key=v with a name of letters, digits and _.+- "
                      "(got '" +
                          c.name + "')");
  if (colon == std::string::npos) return c;
  const std::string rest = std::string(io::Trim(arg.substr(colon + 1)));
  if (rest.empty()) return c;
  for (const auto& o : SplitTopLevel(rest)) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError(where, "",
                        "override '" + o + "' must look like key=value (name:key=v,key=v)");
    c.overrides.push_back(o);
  }
  return c;
}

SweepDefinition ParseSweepArguments(const SweepArguments& a) {
  SweepDefinition d;
  d.scenario_file = a.scenario;
  d.base_overrides = a.overrides;
  d.stability_file = a.stability;
  d.stop_at_first_abort = a.stop_at_first_abort;
  // Every malformed argument at once.
  std::vector<Problem> problems;
  for (const auto& v : a.vary) try {
      d.axes.push_back(ParseVary(v));
    } catch (const ConfigError& e) {
      problems.push_back({e.file(), e.problems().front().message});
    }
  for (const auto& c : a.configs) try {
      d.configs.push_back(ParseConfig(c));
    } catch (const ConfigError& e) {
      problems.push_back({e.file(), e.problems().front().message});
    }
  if (!problems.empty()) throw ConfigError("scw sweep", problems);
  return d;
}

std::vector<TraceCondition> ParseTraceConditions(const std::vector<SweepAxis>& axes,
                                                 const std::vector<std::string>& at) {
  std::vector<TraceCondition> out;
  Problems problems;
  for (const auto& c : at) {
    const auto eq = c.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == c.size()) {
      problems.Add("--trace-at " + c, "must look like key=value (key: config or a varied key)");
      continue;
    }
    const std::string key = c.substr(0, eq);
    int axis = -2;
    if (key == "config") axis = -1;
    for (std::size_t i = 0; i < axes.size(); ++i)
      if (axes[i].key == key) axis = static_cast<int>(i);
    if (axis == -2) {
      std::string known = "config";
      for (const auto& a : axes) known += ", " + a.key;
      problems.Add("--trace-at " + c,
                   "'" + key + "' is neither config nor a varied key (" + known + ")");
      continue;
    }
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const TraceCondition& x) { return x.axis == axis; });
    if (it == out.end()) it = out.insert(out.end(), TraceCondition{axis, {}});
    it->values.push_back(c.substr(eq + 1));
  }
  if (!problems.empty()) throw ConfigError("scw sweep", problems.items());
  return out;
}

bool SameSweepValue(const std::string& have, const std::string& want) {
  double x, y;
  if (ParseNumber(have, &x) && ParseNumber(want, &y))
    return std::abs(x - y) <= 1e-9 * std::max({1.0, std::abs(x), std::abs(y)});
  return have == want;
}

}  // namespace scw::tuning::sweep
