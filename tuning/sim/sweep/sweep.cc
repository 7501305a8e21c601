#include "tuning/sim/sweep/sweep.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "params/io/csv.h"
#include "params/io/text.h"
#include "params/io/write.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/parallel/mpi_backend.h"
#include "tuning/sim/parallel/parallel_for.h"
#include "tuning/sim/parallel/wire.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

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

std::string VaryText(const SweepAxis& a) {
  std::string s = "--vary " + a.key + "=";
  for (std::size_t i = 0; i < a.values.size(); ++i) s += (i ? "," : "") + a.values[i];
  return s;
}

std::string ConfigText(const SweepConfig& c) {
  std::string s = "--config " + c.name;
  for (std::size_t i = 0; i < c.overrides.size(); ++i) s += (i ? "," : ":") + c.overrides[i];
  return s;
}

std::string FirstProblems(const ConfigError& e) {
  std::string out;
  for (const auto& p : e.problems()) {
    if (!out.empty()) out += "; ";
    out += p.path.empty() ? p.message : p.path + ": " + p.message;
  }
  return out.empty() ? std::string(e.what()) : out;
}

params::ScenarioParams BaseScenario(const SweepDefinition& d,
                                    const std::vector<std::string>& overrides) {
  params::ScenarioParams spec = d.scenario_file.empty() ? DefaultScenario(overrides)
                                                        : LoadScenario(d.scenario_file, overrides);
  if (!d.stability_file.empty()) spec.stability = fs::absolute(d.stability_file).string();
  return spec;
}

/// The scenario with the keys only the closed loop reads reset: equal texts resolve equally.
std::string ResolveKey(params::ScenarioParams spec) {
  const params::ScenarioParams defaults;
  spec.name = defaults.name;
  spec.subsystems = defaults.subsystems;
  spec.abort = defaults.abort;
  spec.laps = defaults.laps;
  return params::ToPlainYaml(spec);
}

struct Condition {
  int axis = -1;  ///< -1 = config
  std::vector<std::string> values;
};

std::vector<Condition> ParseConditions(const std::vector<SweepAxis>& axes,
                                       const std::vector<std::string>& at) {
  std::vector<Condition> out;
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
    auto it =
        std::find_if(out.begin(), out.end(), [&](const Condition& x) { return x.axis == axis; });
    if (it == out.end()) it = out.insert(out.end(), Condition{axis, {}});
    it->values.push_back(c.substr(eq + 1));
  }
  if (!problems.empty()) throw ConfigError("scw sweep", problems.items());
  return out;
}

bool SameValue(const std::string& a, const std::string& b) {
  double x, y;
  if (ParseNumber(a, &x) && ParseNumber(b, &y))
    return std::abs(x - y) <= 1e-9 * std::max({1.0, std::abs(x), std::abs(y)});
  return a == b;
}

bool Matches(const SweepResult& r, const SweepRun& run, const std::vector<Condition>& conds) {
  for (const auto& c : conds) {
    const std::string& have = c.axis < 0
                                  ? r.configs[static_cast<std::size_t>(run.point.config)].name
                                  : r.axes[static_cast<std::size_t>(c.axis)]
                                        .values[static_cast<std::size_t>(run.point.value[c.axis])];
    if (std::none_of(c.values.begin(), c.values.end(),
                     [&](const std::string& v) { return SameValue(have, v); }))
      return false;
  }
  return true;
}

std::string SafeFilePart(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '+' ||
          c == '-'))
      c = '_';
  return out;
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

std::vector<GridPoint> ExpandGrid(const std::vector<SweepAxis>& axes, int n_configs) {
  std::vector<GridPoint> out;
  const std::size_t n_axes = axes.size();
  for (const auto& a : axes)
    if (a.values.empty()) return out;
  // Axes 2..n as a mixed-radix number (last axis fastest), the first axis innermost.
  long outer = 1;
  for (std::size_t i = 1; i < n_axes; ++i) outer *= static_cast<long>(axes[i].values.size());
  const int n_first = n_axes ? static_cast<int>(axes[0].values.size()) : 1;
  int series = 0;
  for (int c = 0; c < n_configs; ++c) {
    for (long o = 0; o < outer; ++o, ++series) {
      std::vector<int> idx(n_axes, 0);
      long rest = o;
      for (std::size_t i = n_axes; i-- > 1;) {
        const long size = static_cast<long>(axes[i].values.size());
        idx[i] = static_cast<int>(rest % size);
        rest /= size;
      }
      for (int k = 0; k < n_first; ++k) {
        GridPoint p;
        p.config = c;
        p.value = idx;
        if (n_axes) p.value[0] = k;
        p.series = series;
        out.push_back(std::move(p));
      }
    }
  }
  return out;
}

std::vector<bool> ReportedRuns(const std::vector<int>& series, const std::vector<bool>& aborted,
                               bool stop_at_first_abort) {
  std::vector<bool> out(series.size(), true);
  if (!stop_at_first_abort) return out;
  std::map<int, bool> stopped;
  for (std::size_t i = 0; i < series.size(); ++i) {
    bool& s = stopped[series[i]];
    out[i] = !s;
    if (aborted[i]) s = true;
  }
  return out;
}

params::ScenarioParams PointScenario(const SweepDefinition& d, const GridPoint& p) {
  std::vector<std::string> o = d.base_overrides;
  if (!d.configs.empty()) {
    const auto& c = d.configs[static_cast<std::size_t>(p.config)];
    o.insert(o.end(), c.overrides.begin(), c.overrides.end());
  }
  for (std::size_t i = 0; i < d.axes.size(); ++i)
    o.push_back(d.axes[i].key + "=" + d.axes[i].values[static_cast<std::size_t>(p.value[i])]);
  return BaseScenario(d, o);
}

void ValidateSweep(const SweepDefinition& d) {
  // The base scenario first: its errors name the file or --set themselves.
  (void)BaseScenario(d, d.base_overrides);
  Problems problems;
  for (std::size_t i = 0; i < d.configs.size(); ++i) {
    const auto& c = d.configs[i];
    for (std::size_t j = 0; j < i; ++j)
      if (d.configs[j].name == c.name)
        problems.Add(ConfigText(c), "configuration name '" + c.name + "' is used twice");
    std::vector<std::string> o = d.base_overrides;
    o.insert(o.end(), c.overrides.begin(), c.overrides.end());
    try {
      (void)BaseScenario(d, o);
    } catch (const ConfigError& e) {
      problems.Add(ConfigText(c), FirstProblems(e));
    }
  }
  for (std::size_t i = 0; i < d.axes.size(); ++i) {
    const auto& a = d.axes[i];
    for (std::size_t j = 0; j < i; ++j)
      if (d.axes[j].key == a.key) problems.Add(VaryText(a), "key '" + a.key + "' is varied twice");
    for (std::size_t k = 0; k < a.values.size(); ++k) {
      for (std::size_t j = 0; j < k; ++j)
        if (a.values[j] == a.values[k])
          problems.Add(VaryText(a), "value '" + a.values[k] + "' is given twice");
      std::vector<std::string> o = d.base_overrides;
      o.push_back(a.key + "=" + a.values[k]);
      try {
        (void)BaseScenario(d, o);
      } catch (const ConfigError& e) {
        problems.Add(VaryText(a), FirstProblems(e));
        break;  // one message per argument
      }
    }
  }
  if (!problems.empty()) throw ConfigError("scw sweep", problems.items());
}

namespace {

// The grid with every run's scenario and its resolution group (shared by RunSweep and the
// worker processes, so both number and resolve the runs identically).
struct SweepPlan {
  SweepResult r;
  std::vector<GridPoint> grid;
  std::vector<int> run_resolve;                      ///< per run: index into unique_specs
  std::vector<params::ScenarioParams> unique_specs;  ///< one per distinct resolution
  std::string base_dir, source;
};

SweepPlan MakePlan(const SweepDefinition& d) {
  ValidateSweep(d);
  SweepPlan plan;
  SweepResult& r = plan.r;
  r.axes = d.axes;
  r.configs = d.configs.empty() ? std::vector<SweepConfig>{{"default", {}}} : d.configs;
  plan.grid = ExpandGrid(d.axes, static_cast<int>(r.configs.size()));
  const int n = static_cast<int>(plan.grid.size());
  r.runs.resize(plan.grid.size());
  plan.run_resolve.resize(plan.grid.size());
  // Scenarios (serially: cheap, and errors come out in run order), grouped by resolution.
  std::map<std::string, int> resolve_index;
  for (int i = 0; i < n; ++i) {
    SweepRun& run = r.runs[static_cast<std::size_t>(i)];
    run.point = plan.grid[static_cast<std::size_t>(i)];
    run.spec = PointScenario(d, run.point);
    const auto [it, added] =
        resolve_index.emplace(ResolveKey(run.spec), static_cast<int>(plan.unique_specs.size()));
    if (added) plan.unique_specs.push_back(run.spec);
    plan.run_resolve[static_cast<std::size_t>(i)] = it->second;
  }
  r.resolves = static_cast<int>(plan.unique_specs.size());
  plan.base_dir =
      d.scenario_file.empty() ? std::string() : fs::path(d.scenario_file).parent_path().string();
  plan.source = d.scenario_file.empty() ? "built-in" : d.scenario_file;
  return plan;
}

// Resolutions on demand, each at most once; Get and Scenario may run in parallel (a thread that
// needs a resolution in flight waits for it).
class Resolutions {
 public:
  explicit Resolutions(const SweepPlan& plan)
      : plan_(plan), done_(plan.unique_specs.size()), once_(plan.unique_specs.size()) {}
  const ResolvedScenario& Get(int k) {
    const auto at = static_cast<std::size_t>(k);
    std::call_once(once_[at], [&] {
      done_[at] = std::make_unique<ResolvedScenario>(
          Resolve(plan_.unique_specs[at], plan_.base_dir, plan_.source));
    });
    return *done_[at];
  }
  /// The scenario of run i: its group's resolution with the run's own spec.
  ResolvedScenario Scenario(int i) {
    ResolvedScenario sc = Get(plan_.run_resolve[static_cast<std::size_t>(i)]);
    sc.spec = plan_.r.runs[static_cast<std::size_t>(i)].spec;
    return sc;
  }

 private:
  const SweepPlan& plan_;
  std::vector<std::unique_ptr<ResolvedScenario>> done_;
  std::vector<std::once_flag> once_;
};

// --- Run results between processes: the run's metrics as exact text (EncodeRunMetrics), then
// the reference's ideal lap time the same way.
std::string EncodeRun(const RunMetrics& m, double ideal_lap_time) {
  char buf[64];
  std::snprintf(buf, sizeof buf, " %a", ideal_lap_time);
  return EncodeRunMetrics(m) + buf;
}

bool DecodeRun(const char* text, RunMetrics* m, double* ideal_lap_time) {
  const char* p = DecodeRunMetrics(text, m);
  if (p == nullptr) return false;
  char* end = nullptr;
  *ideal_lap_time = std::strtod(p, &end);
  if (end == p) return false;
  p = end;
  while (*p == ' ') ++p;
  return *p == '\0' || *p == '\n';
}

std::string OneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = '\x1f';
  return s;
}
std::string Multiline(std::string s) {
  for (char& c : s)
    if (c == '\x1f') c = '\n';
  return s;
}

std::string RunLabel(const SweepResult& r, int i) {
  const SweepRun& run = r.runs[static_cast<std::size_t>(i)];
  std::string s = "run " + std::to_string(i + 1) + " (config " +
                  r.configs[static_cast<std::size_t>(run.point.config)].name;
  for (std::size_t a = 0; a < r.axes.size(); ++a)
    s +=
        ", " + r.axes[a].key + "=" + r.axes[a].values[static_cast<std::size_t>(run.point.value[a])];
  return s + ")";
}

// --- MPI ranks (tuning/sim/parallel/mpi_backend.h): the definition goes to every rank, which
// builds the same plan and resolves what its runs need; a batch is a list of run indices. A run's
// answer is "ok" + EncodeRun, or "C " / "R " + the message of a ConfigError / another error.
std::string EncodeDefinition(const SweepDefinition& d) {
  WireWriter w;
  const auto strings = [&w](const std::vector<std::string>& v) {
    w.Int(static_cast<std::int64_t>(v.size()));
    for (const auto& x : v) w.String(x);
  };
  w.String(d.scenario_file);
  strings(d.base_overrides);
  w.String(d.stability_file);
  w.Int(static_cast<std::int64_t>(d.axes.size()));
  for (const auto& a : d.axes) {
    w.String(a.key);
    strings(a.values);
  }
  w.Int(static_cast<std::int64_t>(d.configs.size()));
  for (const auto& c : d.configs) {
    w.String(c.name);
    strings(c.overrides);
  }
  w.Bool(d.stop_at_first_abort);
  return w.Take();
}

SweepDefinition DecodeDefinition(std::string_view bytes) {
  WireReader r(bytes);
  const auto strings = [&r] {
    std::vector<std::string> v(static_cast<std::size_t>(r.Int()));
    for (auto& x : v) x = r.String();
    return v;
  };
  SweepDefinition d;
  d.scenario_file = r.String();
  d.base_overrides = strings();
  d.stability_file = r.String();
  d.axes.resize(static_cast<std::size_t>(r.Int()));
  for (auto& a : d.axes) {
    a.key = r.String();
    a.values = strings();
  }
  d.configs.resize(static_cast<std::size_t>(r.Int()));
  for (auto& c : d.configs) {
    c.name = r.String();
    c.overrides = strings();
  }
  d.stop_at_first_abort = r.Bool();
  return d;
}

std::string RunAnswer(Resolutions* resolutions, int i) {
  try {
    const ResolvedScenario sc = resolutions->Scenario(i);
    return "ok" + EncodeRun(RunClosedLoop(sc, sc.stability), sc.ideal_lap_time);
  } catch (const ConfigError& e) {
    return std::string("C ") + e.what();
  } catch (const std::exception& e) {
    return std::string("R ") + e.what();
  }
}

// Fills run i from its answer; a failed run throws as with worker processes.
void ApplyAnswer(SweepResult* r, int i, std::string_view answer) {
  const std::string a(answer);
  SweepRun& run = r->runs[static_cast<std::size_t>(i)];
  if (a.rfind("ok", 0) == 0) {
    if (!DecodeRun(a.c_str() + 2, &run.metrics, &run.ideal_lap_time))
      throw std::runtime_error("an MPI rank sent unreadable results for " + RunLabel(*r, i));
    run.computed = true;
    return;
  }
  const std::string message = RunLabel(*r, i) + ": " + (a.size() > 2 ? a.substr(2) : a);
  if (a.rfind("C ", 0) == 0) throw ConfigError("scw sweep", "", message);
  throw std::runtime_error(message);
}

class SweepWorkerTask final : public mpi::WorkerTask {
 public:
  explicit SweepWorkerTask(std::string_view setup)
      : plan_(MakePlan(DecodeDefinition(setup))), resolutions_(plan_) {}

  void StartBatch(std::string_view payload) override {
    WireReader r(payload);
    batch_.resize(static_cast<std::size_t>(r.Int()));
    for (int& i : batch_) i = static_cast<int>(r.Int());
  }

  std::string Run(int index) const override {
    if (index < 0 || static_cast<std::size_t>(index) >= batch_.size())
      throw std::runtime_error("job index out of range");
    const int i = batch_[static_cast<std::size_t>(index)];
    if (i < 0 || static_cast<std::size_t>(i) >= plan_.grid.size())
      throw std::runtime_error("run index out of range");
    return RunAnswer(&resolutions_, i);
  }

 private:
  SweepPlan plan_;
  mutable Resolutions resolutions_;
  std::vector<int> batch_;
};

// Worker processes: `argv` + "--worker-fd=3"; each reads "run <i>" lines on its stdin and answers
// "ok <i> <EncodeRun>" or "error <i> <C|R> <message>" on fd 3 (its stdout goes to stderr so
// stray output cannot corrupt the protocol). One job per worker at a time, so no pipe can fill.
class WorkerPool {
 public:
  WorkerPool(std::vector<std::string> argv, int n, const SweepResult& r) : r_(r) {
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, &old_sigpipe_);  // a dead worker's pipe: EPIPE, not death
    argv.push_back("--worker-fd=3");
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    for (int w = 0; w < n; ++w) {
      int to[2], from[2];
      if (pipe2(to, O_CLOEXEC) != 0) Fail("cannot create a pipe");
      if (pipe2(from, O_CLOEXEC) != 0) {
        close(to[0]);
        close(to[1]);
        Fail("cannot create a pipe");
      }
      const pid_t pid = fork();
      if (pid == 0) {  // child: async-signal-safe calls only
        if (dup2(to[0], 0) < 0 || dup2(from[1], 3) < 0 || dup2(2, 1) < 0) _exit(127);
        execv(cargv[0], cargv.data());
        _exit(127);
      }
      close(to[0]);
      close(from[1]);
      if (pid < 0) {
        close(to[1]);
        close(from[0]);
        Fail("cannot start a worker process");
      }
      workers_.push_back({pid, to[1], from[0], {}, -1});
    }
  }
  ~WorkerPool() {
    for (auto& w : workers_) {
      if (w.to >= 0) close(w.to);
      if (w.from >= 0) close(w.from);
      if (w.pid > 0) {
        kill(w.pid, SIGTERM);
        waitpid(w.pid, nullptr, 0);
      }
    }
    sigaction(SIGPIPE, &old_sigpipe_, nullptr);
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Runs `jobs` on the workers; on_result(i, payload) for every answer "ok". Errors of runs are
  /// rethrown after the batch (the first by index); a worker that dies throws at once.
  void Run(const std::vector<int>& jobs, const std::function<void(int, const char*)>& on_result) {
    std::size_t next = 0, pending = 0;
    std::map<int, std::pair<bool, std::string>> errors;  // run → (config error, message)
    const auto assign = [&](Worker& w) {
      if (next >= jobs.size()) return;
      w.job = jobs[next++];
      const std::string line = "run " + std::to_string(w.job) + "\n";
      if (!WriteAll(w.to, line)) Died(w);
      ++pending;
    };
    for (auto& w : workers_) assign(w);
    std::vector<pollfd> fds(workers_.size());
    while (pending > 0) {
      for (std::size_t k = 0; k < workers_.size(); ++k)
        fds[k] = {workers_[k].job >= 0 ? workers_[k].from : -1, POLLIN, 0};
      if (poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        Fail("poll failed");
      }
      for (std::size_t k = 0; k < workers_.size(); ++k) {
        if (fds[k].revents == 0) continue;
        Worker& w = workers_[k];
        char buf[4096];
        const ssize_t got = read(w.from, buf, sizeof buf);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) Died(w);
        w.buf.append(buf, static_cast<std::size_t>(got));
        std::size_t eol;
        while ((eol = w.buf.find('\n')) != std::string::npos) {
          const std::string line = w.buf.substr(0, eol);
          w.buf.erase(0, eol + 1);
          int job = -1, used = 0;
          if (line.rfind("ok ", 0) == 0 && std::sscanf(line.c_str(), "ok %d%n", &job, &used) == 1 &&
              job == w.job) {
            on_result(job, line.c_str() + used);
          } else if (line.rfind("error ", 0) == 0 &&
                     std::sscanf(line.c_str(), "error %d%n", &job, &used) == 1 && job == w.job &&
                     line.size() > static_cast<std::size_t>(used) + 2) {
            const bool config = line[static_cast<std::size_t>(used) + 1] == 'C';
            errors[job] = {config, Multiline(line.substr(static_cast<std::size_t>(used) + 3))};
          } else {
            Fail("sweep worker process " + std::to_string(w.pid) + " sent an unreadable line for " +
                 RunLabel(r_, w.job) + ": '" + line.substr(0, 200) + "'");
          }
          w.job = -1;
          --pending;
          assign(w);
        }
      }
    }
    if (!errors.empty()) {
      const auto& [job, e] = *errors.begin();
      if (e.first) throw ConfigError("scw sweep", "", RunLabel(r_, job) + ": " + e.second);
      throw std::runtime_error(RunLabel(r_, job) + ": " + e.second);
    }
  }

  /// Ends the workers (EOF on their input) and checks that each exited with 0.
  void Finish() {
    for (auto& w : workers_) {
      close(w.to);
      w.to = -1;
    }
    for (auto& w : workers_) {
      int status = 0;
      const pid_t pid = w.pid;
      waitpid(pid, &status, 0);
      w.pid = -1;
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        Fail("sweep worker process " + std::to_string(pid) + " " + StatusText(status) +
             " at the end of the sweep");
    }
  }

 private:
  struct Worker {
    pid_t pid;
    int to, from;
    std::string buf;
    int job;
  };

  static bool WriteAll(int fd, const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
      const ssize_t n = write(fd, s.data() + done, s.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }
  static std::string StatusText(int status) {
    if (WIFSIGNALED(status))
      return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
             strsignal(WTERMSIG(status)) + ")";
    if (WIFEXITED(status)) {
      if (WEXITSTATUS(status) == 127) return "could not be started (exit code 127)";
      return "exited with code " + std::to_string(WEXITSTATUS(status));
    }
    return "ended abnormally";
  }
  [[noreturn]] void Died(Worker& w) {
    int status = 0;
    const pid_t pid = w.pid;
    if (w.from >= 0) close(w.from);
    w.from = -1;
    kill(pid, SIGTERM);
    waitpid(pid, &status, 0);
    w.pid = -1;
    Fail("sweep worker process " + std::to_string(pid) + " " + StatusText(status) +
         " while computing " + RunLabel(r_, w.job) + "; no table written");
  }
  [[noreturn]] static void Fail(const std::string& what) { throw std::runtime_error(what); }

  const SweepResult& r_;
  std::vector<Worker> workers_;
  struct sigaction old_sigpipe_ {};
};

}  // namespace

std::unique_ptr<mpi::WorkerTask> MakeSweepWorkerTask(std::string_view setup, int /*threads*/) {
  return std::make_unique<SweepWorkerTask>(setup);
}

SweepResult RunSweep(const SweepDefinition& d, int threads, const SweepTraceOptions& traces) {
  SweepExecution exec;
  exec.threads = threads;
  return RunSweep(d, exec, traces);
}

std::vector<std::string> SweepWorkerArguments(const SweepDefinition& d) {
  std::vector<std::string> a;
  if (!d.scenario_file.empty()) a.push_back("--scenario=" + d.scenario_file);
  for (const auto& o : d.base_overrides) a.push_back("--set=" + o);
  if (!d.stability_file.empty()) a.push_back("--stability=" + d.stability_file);
  for (const auto& axis : d.axes) {
    std::string v = "--vary=" + axis.key + "=";
    for (std::size_t i = 0; i < axis.values.size(); ++i) v += (i ? "," : "") + axis.values[i];
    a.push_back(v);
  }
  for (const auto& c : d.configs) a.push_back("--config=" + ConfigText(c).substr(9));
  return a;
}

int RunSweepWorker(const SweepDefinition& d, int in_fd, int out_fd) {
  SweepPlan plan = MakePlan(d);
  Resolutions resolutions(plan);
  FILE* in = fdopen(in_fd, "r");
  FILE* out = fdopen(out_fd, "w");
  if (in == nullptr || out == nullptr) return 1;
  char line[256];
  const int n = static_cast<int>(plan.grid.size());
  while (std::fgets(line, sizeof line, in) != nullptr) {
    int i = -1;
    if (std::sscanf(line, "run %d", &i) != 1 || i < 0 || i >= n) return 1;
    std::string answer;
    try {
      const ResolvedScenario sc = resolutions.Scenario(i);
      answer =
          "ok " + std::to_string(i) + EncodeRun(RunClosedLoop(sc, sc.stability), sc.ideal_lap_time);
    } catch (const ConfigError& e) {
      answer = "error " + std::to_string(i) + " C " + OneLine(e.what());
    } catch (const std::exception& e) {
      answer = "error " + std::to_string(i) + " R " + OneLine(e.what());
    }
    if (std::fputs((answer + "\n").c_str(), out) < 0 || std::fflush(out) != 0) return 1;
  }
  return 0;
}

SweepResult RunSweep(const SweepDefinition& d, const SweepExecution& exec,
                     const SweepTraceOptions& traces) {
  SweepPlan plan = MakePlan(d);
  SweepResult& r = plan.r;
  const auto conditions = ParseConditions(r.axes, traces.at);
  const std::vector<GridPoint>& grid = plan.grid;
  const int n = static_cast<int>(grid.size());
  const int threads = exec.threads;
  Resolutions resolutions(plan);

  // Progress (reporting only): runs computed so far of the runs that will be computed.
  std::mutex progress_mutex;
  SweepProgress progress{"run", 0, n};
  const auto report = [&](int more_done) {
    if (!exec.on_progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.done += more_done;
    exec.on_progress(progress);
  };
  report(0);

  // How a batch of runs is computed: threads of this process (resolutions first, in parallel),
  // or worker processes (each resolves what it needs).
  std::unique_ptr<WorkerPool> pool;
  std::function<void(const std::vector<int>&)> run_batch;
  int workers = ResolveThreads(threads);
  std::shared_ptr<const mpi::RemoteTask> remote;
  if (exec.processes == 0)
    remote = mpi::MaybeRemote(
        "sweep", [&] { return EncodeDefinition(d); }, workers);
  if (remote) {
    // MPI: every rank (this one included, `threads` each) takes runs as it becomes free.
    workers = mpi::Ranks() * remote->threads();
    run_batch = [&](const std::vector<int>& batch) {
      WireWriter w;
      w.Int(static_cast<std::int64_t>(batch.size()));
      for (int i : batch) w.Int(i);
      remote->Run(
          w.Take(), static_cast<int>(batch.size()),
          [&](int k) {
            const int i = batch[static_cast<std::size_t>(k)];
            ApplyAnswer(&r, i, RunAnswer(&resolutions, i));
            report(1);
          },
          [&](int k, std::string_view answer) {
            ApplyAnswer(&r, batch[static_cast<std::size_t>(k)], answer);
            report(1);
          });
    };
  } else if (exec.processes > 0) {
    if (exec.worker_command.empty())
      throw std::invalid_argument("RunSweep: processes need a worker command");
    workers = std::min(exec.processes, std::max(n, 1));
    std::vector<std::string> argv = exec.worker_command;
    for (auto& a : SweepWorkerArguments(d)) argv.push_back(std::move(a));
    pool = std::make_unique<WorkerPool>(argv, workers, r);
    run_batch = [&](const std::vector<int>& batch) {
      pool->Run(batch, [&](int i, const char* payload) {
        SweepRun& run = r.runs[static_cast<std::size_t>(i)];
        if (!DecodeRun(payload, &run.metrics, &run.ideal_lap_time))
          throw std::runtime_error("sweep worker sent unreadable results for " + RunLabel(r, i));
        run.computed = true;
        report(1);
      });
    };
  } else {
    run_batch = [&](const std::vector<int>& batch) {
      // The batch's resolutions first, in parallel (only those a run needs: a series stopped at
      // its first abort never resolves its later values).
      std::vector<int> groups;
      for (int i : batch) groups.push_back(plan.run_resolve[static_cast<std::size_t>(i)]);
      std::sort(groups.begin(), groups.end());
      groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
      ParallelFor(static_cast<int>(groups.size()), threads,
                  [&](int k) { (void)resolutions.Get(groups[static_cast<std::size_t>(k)]); });
      ParallelFor(static_cast<int>(batch.size()), threads, [&](int k) {
        const int i = batch[static_cast<std::size_t>(k)];
        const ResolvedScenario sc = resolutions.Scenario(i);
        SweepRun& run = r.runs[static_cast<std::size_t>(i)];
        run.metrics = RunClosedLoop(sc, sc.stability);
        run.ideal_lap_time = sc.ideal_lap_time;
        run.computed = true;
        report(1);
      });
    };
  }

  if (!d.stop_at_first_abort) {
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
    run_batch(all);
  } else {
    // Waves: the next few runs of every series still going, in parallel; a series stops after
    // its first abort. Which runs get computed depends on the worker count, the reported ones
    // (every run up to the first abort) do not.
    int n_series = 0;
    for (const auto& p : grid) n_series = std::max(n_series, p.series + 1);
    std::vector<std::vector<int>> members(static_cast<std::size_t>(n_series));
    for (int i = 0; i < n; ++i)
      members[static_cast<std::size_t>(grid[static_cast<std::size_t>(i)].series)].push_back(i);
    std::vector<std::size_t> next(members.size(), 0);
    std::vector<bool> stopped(members.size(), false);
    while (true) {
      std::vector<std::size_t> alive;
      for (std::size_t s = 0; s < members.size(); ++s)
        if (!stopped[s] && next[s] < members[s].size()) alive.push_back(s);
      if (alive.empty()) break;
      const std::size_t per = std::max<std::size_t>(
          1, (static_cast<std::size_t>(workers) + alive.size() - 1) / alive.size());
      std::vector<int> batch;
      for (std::size_t s : alive)
        for (std::size_t k = next[s]; k < std::min(next[s] + per, members[s].size()); ++k)
          batch.push_back(members[s][k]);
      run_batch(batch);
      for (std::size_t s : alive) {
        const std::size_t end = std::min(next[s] + per, members[s].size());
        for (; next[s] < end && !stopped[s]; ++next[s])
          if (r.runs[static_cast<std::size_t>(members[s][next[s]])].metrics.aborted())
            stopped[s] = true;
      }
      if (exec.on_progress) {
        // The runs still to come: those after each going series' last computed run.
        int total = progress.done;
        for (std::size_t s = 0; s < members.size(); ++s)
          if (!stopped[s])
            for (std::size_t k = next[s]; k < members[s].size(); ++k)
              total += !r.runs[static_cast<std::size_t>(members[s][k])].computed;
        progress.total = total;
        report(0);
      }
    }
  }
  if (pool) {
    pool->Finish();
    pool.reset();
  }

  std::vector<int> series(grid.size());
  std::vector<bool> aborted(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    series[i] = r.runs[i].point.series;
    // A run not computed comes after its series' first abort: never reported.
    aborted[i] = !r.runs[i].computed || r.runs[i].metrics.aborted();
  }
  const std::vector<bool> reported = ReportedRuns(series, aborted, d.stop_at_first_abort);
  for (std::size_t i = 0; i < grid.size(); ++i) r.runs[i].reported = reported[i];

  if (!traces.dir.empty()) {
    std::vector<int> selected;
    for (int i = 0; i < n; ++i) {
      const SweepRun& run = r.runs[static_cast<std::size_t>(i)];
      if (run.reported && Matches(r, run, conditions)) selected.push_back(i);
    }
    // Resolutions of the traced runs first (serially: with worker processes none exist here).
    for (int i : selected) (void)resolutions.Get(plan.run_resolve[static_cast<std::size_t>(i)]);
    std::error_code ec;
    fs::create_directories(traces.dir, ec);
    if (ec)
      throw std::runtime_error("cannot create the trace folder " + traces.dir + ": " +
                               ec.message());
    {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress = {"trace", 0, static_cast<int>(selected.size())};
    }
    report(0);
    ParallelFor(static_cast<int>(selected.size()), threads, [&](int k) {
      const int i = selected[static_cast<std::size_t>(k)];
      const ResolvedScenario sc = resolutions.Scenario(i);
      io::CsvWriter w(
          (fs::path(traces.dir) / TraceFileName(r, r.runs[static_cast<std::size_t>(i)])).string(),
          TraceHeader());
      RunOptions ro;
      ro.trace = &w;
      (void)RunClosedLoop(sc, sc.stability, ro);
      w.Commit();
      report(1);
    });
  }
  return std::move(plan.r);
}

bool MatchesTraceConditions(const SweepResult& r, const SweepRun& run,
                            const std::vector<std::string>& at) {
  return Matches(r, run, ParseConditions(r.axes, at));
}

std::string TraceFileName(const SweepResult& r, const SweepRun& run) {
  std::string name = SafeFilePart(r.configs[static_cast<std::size_t>(run.point.config)].name);
  for (std::size_t i = 0; i < r.axes.size(); ++i)
    name += "__" + SafeFilePart(r.axes[i].key) + "-" +
            SafeFilePart(r.axes[i].values[static_cast<std::size_t>(run.point.value[i])]);
  return name + ".csv";
}

void WriteSweepCsv(const std::string& path, const SweepResult& r) {
  int max_laps = 0;
  for (const auto& run : r.runs) max_laps = std::max(max_laps, run.spec.laps);
  std::vector<std::string> header = {"config"};
  for (const auto& a : r.axes) header.push_back(a.key);  // CsvWriter quotes (RFC 4180)
  for (const char* h : {"status", "progress", "laps_completed"}) header.emplace_back(h);
  for (int k = 1; k <= max_laps; ++k) header.push_back("lap_" + std::to_string(k) + "_s");
  // The RunMetrics columns (names, units and conversions: RunMetrics::Visit).
  static constexpr std::string_view kColumns[] = {kMeanLapTimeKey,
                                                  "max_abs_sideslip_deg",
                                                  "max_slip_front_pct",
                                                  "max_slip_rear_pct",
                                                  "max_abs_lateral_error_m",
                                                  "max_abs_heading_error_deg",
                                                  "max_speed_mps",
                                                  "esc_count",
                                                  "cs_count",
                                                  "abs_count",
                                                  "tc_count",
                                                  "esc_time_s",
                                                  "cs_time_s",
                                                  "abs_time_s",
                                                  "tc_time_s",
                                                  "esc_brake_energy_J",
                                                  "end_lap",
                                                  "end_s_m"};
  for (std::string_view c : kColumns) header.emplace_back(c);
  header.emplace_back("ideal_lap_time_s");
  io::CsvWriter w(path, header);
  for (const auto& run : r.runs) {
    if (!run.reported) continue;
    const RunMetrics& m = run.metrics;
    w.Add(r.configs[static_cast<std::size_t>(run.point.config)].name);
    for (std::size_t i = 0; i < r.axes.size(); ++i)
      w.Add(r.axes[i].values[static_cast<std::size_t>(run.point.value[i])]);
    w.Add(std::string(RunStatusName(m.status)));
    w.Add(m.Progress());
    w.Add(static_cast<int>(m.lap_times.size()));
    for (int k = 0; k < max_laps; ++k)
      w.Add(k < static_cast<int>(m.lap_times.size()) ? m.lap_times[static_cast<std::size_t>(k)]
                                                     : std::nan(""));
    for (std::string_view c : kColumns) {
      const MetricValue v = RenderedMetric(m, c);
      if (v.is_integer)
        w.Add(static_cast<int>(v.integer));
      else
        w.Add(v.real);
    }
    w.Add(run.ideal_lap_time);
    w.EndRow();
  }
  w.Commit();
}

}  // namespace scw::tuning
