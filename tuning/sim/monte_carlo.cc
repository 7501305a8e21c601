#include "tuning/sim/monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "params/io/write.h"
#include "params/schema/scenario_params.h"

namespace scw::tuning {
namespace {

using params::YamlNode;

// splitmix64: a small, well-mixed generator whose output is the same on every platform (the
// standard library's distributions are not), so a draw depends only on (seed, index, key order).
std::uint64_t Mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform in [0, 1) from the top 53 bits.
double Unit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

template <class T>
struct IsList : std::false_type {};
template <class T, class A>
struct IsList<std::vector<T, A>> : std::true_type {};

// The schema kind of a scenario key: -1 unknown, 0 scalar, 1 list.
int KeyKind(const std::string& key) {
  params::ScenarioParams p;
  int kind = -1;
  params::ForEachField(p, [&](const std::string& path, auto& value, const params::Meta&) {
    if (path != key) return;
    kind = IsList<std::decay_t<decltype(value)>>::value ? 1 : 0;
  });
  return kind;
}

bool ScalarList(const YamlNode& n, std::vector<std::string>* out) {
  if (n.kind != YamlNode::Kind::kSequence || n.items.empty()) return false;
  for (const auto& it : n.items) {
    if (it.kind != YamlNode::Kind::kScalar) return false;
    out->push_back(it.text);
  }
  return true;
}

bool NumberPair(const YamlNode& n, double* lo, double* hi) {
  return n.kind == YamlNode::Kind::kSequence && n.items.size() == 2 &&
         n.items[0].kind == YamlNode::Kind::kScalar && n.items[1].kind == YamlNode::Kind::kScalar &&
         params::ParseDouble(n.items[0].text, lo) && params::ParseDouble(n.items[1].text, hi) &&
         std::isfinite(*lo) && std::isfinite(*hi) && *lo <= *hi;
}

std::string Line(const YamlNode& n) { return " (line " + std::to_string(n.line) + ")"; }

MonteCarloDraw ReadDraw(const std::string& key, const YamlNode& v, const std::string& at,
                        Problems* pr) {
  MonteCarloDraw d;
  d.key = key;
  if (v.kind != YamlNode::Kind::kMap) {
    pr->Add(at, "must be a map with one of uniform, integer, choice" + Line(v));
    return d;
  }
  int kinds = 0;
  for (const auto& [k, x] : v.entries) {
    const std::string path = at + "." + k;
    if (k == "uniform" || k == "integer") {
      ++kinds;
      d.kind = k == "uniform" ? MonteCarloDraw::Kind::kUniform : MonteCarloDraw::Kind::kInteger;
      if (!NumberPair(x, &d.lo, &d.hi))
        pr->Add(path, "must be [low, high] with finite numbers, low <= high" + Line(x));
      else if (k == "integer" && (d.lo != std::floor(d.lo) || d.hi != std::floor(d.hi) ||
                                  std::fabs(d.lo) > 1e15 || std::fabs(d.hi) > 1e15))
        pr->Add(path, "the bounds must be whole numbers (|n| <= 1e15)" + Line(x));
    } else if (k == "choice") {
      ++kinds;
      d.kind = MonteCarloDraw::Kind::kChoice;
      if (!ScalarList(x, &d.choices)) pr->Add(path, "must be a non-empty list of values" + Line(x));
    } else if (k == "step") {
      if (x.kind != YamlNode::Kind::kScalar || !params::ParseDouble(x.text, &d.step) ||
          !std::isfinite(d.step) || d.step <= 0)
        pr->Add(path, "must be a number > 0" + Line(x));
    } else {
      pr->Add(path, "unknown key (expected uniform, integer, choice, step)" + Line(x));
    }
  }
  if (kinds != 1) pr->Add(at, "give exactly one of uniform, integer, choice" + Line(v));
  if (d.step > 0 && d.kind != MonteCarloDraw::Kind::kUniform)
    pr->Add(at + ".step", "only a uniform draw takes a step" + Line(v));
  return d;
}

std::string Drawn(const MonteCarloDraw& d, std::uint64_t bits) {
  const double u = Unit(bits);
  switch (d.kind) {
    case MonteCarloDraw::Kind::kChoice: {
      const auto i = std::min(d.choices.size() - 1, static_cast<std::size_t>(u * d.choices.size()));
      return d.choices[i];
    }
    case MonteCarloDraw::Kind::kInteger: {
      const double n = d.hi - d.lo + 1.0;
      const double v = std::min(d.hi, d.lo + std::floor(u * n));
      return std::to_string(static_cast<long long>(v));
    }
    case MonteCarloDraw::Kind::kUniform:
    default: {
      double v = d.lo + u * (d.hi - d.lo);
      if (d.step > 0) {
        // A multiple of step; dividing by a whole 1/step gives the double nearest to the decimal
        // (0.85, not 0.8500000000000001 as 17 × 0.05 would).
        const double inv = std::round(1.0 / d.step);
        v = std::fabs(inv * d.step - 1.0) < 1e-12 ? std::round(v * inv) / inv
                                                  : std::round(v / d.step) * d.step;
        v = std::clamp(v, d.lo, d.hi);
      }
      return params::FormatDouble(v);
    }
  }
}

}  // namespace

std::size_t MonteCarloBlock::Size() const {
  std::size_t n = count > 0 ? static_cast<std::size_t>(count) : 0;
  for (const auto& g : grid) {
    if (g.values.empty()) return 0;
    if (n > kMaxMonteCarloScenarios / g.values.size()) return kMaxMonteCarloScenarios + 1;
    n *= g.values.size();
  }
  return n;
}

std::vector<ScenarioEntry> MonteCarloBlock::Expand() const {
  const std::size_t n = Size();
  std::vector<ScenarioEntry> out;
  if (n == 0 || n > kMaxMonteCarloScenarios) return out;
  const std::size_t width = std::max<std::size_t>(3, std::to_string(n - 1).size());
  std::vector<int> list_key(vary.size() + grid.size());
  for (std::size_t k = 0; k < vary.size(); ++k) list_key[k] = KeyKind(vary[k].key);
  for (std::size_t k = 0; k < grid.size(); ++k) list_key[vary.size() + k] = KeyKind(grid[k].key);
  auto put = [&](ScenarioEntry* e, std::size_t k, const std::string& key, const std::string& v) {
    const bool wrap = list_key[k] == 1 && (v.empty() || v.front() != '[');
    e->overrides.push_back(key + "=" + (wrap ? "[" + v + "]" : v));
  };
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    ScenarioEntry e;
    std::string index = std::to_string(i);
    e.name = name + "_" + std::string(width - index.size(), '0') + index;
    e.weight = weight;
    e.file = file;
    e.overrides = base;
    // Grid point: i / count, first grid key slowest.
    std::size_t point = i / static_cast<std::size_t>(count);
    std::vector<std::size_t> at(grid.size());
    for (std::size_t k = grid.size(); k-- > 0;) {
      at[k] = point % grid[k].values.size();
      point /= grid[k].values.size();
    }
    for (std::size_t k = 0; k < grid.size(); ++k)
      put(&e, vary.size() + k, grid[k].key, grid[k].values[at[k]]);
    // Draws: a stream per scenario index, one number per key in the order written.
    std::uint64_t state = Mix(seed ^ Mix(static_cast<std::uint64_t>(i)));
    for (std::size_t k = 0; k < vary.size(); ++k) {
      state = Mix(state);
      put(&e, k, vary[k].key, Drawn(vary[k], state));
    }
    out.push_back(std::move(e));
  }
  return out;
}

MonteCarloBlock ReadMonteCarloBlock(const YamlNode& node, const std::string& where, Problems* pr) {
  MonteCarloBlock b;
  const std::string line = Line(node);
  if (node.kind != YamlNode::Kind::kMap) {
    pr->Add(where, "must be a map {name, count, seed, weight, file, set, vary, grid}" + line);
    return b;
  }
  auto check_key = [&](const std::string& key, const std::string& path, const YamlNode& n) {
    if (KeyKind(key) < 0) pr->Add(path, "unknown scenario key '" + key + "'" + Line(n));
  };
  for (const auto& [k, v] : node.entries) {
    const std::string path = where + "." + k;
    if (k == "vary" || k == "grid") {
      if (v.kind != YamlNode::Kind::kMap || v.entries.empty()) {
        pr->Add(path, "must be a map of scenario keys" + Line(v));
        continue;
      }
      for (const auto& [key, x] : v.entries) {
        check_key(key, path + "." + key, x);
        if (k == "vary") {
          b.vary.push_back(ReadDraw(key, x, path + "." + key, pr));
        } else {
          MonteCarloGrid g{key, {}};
          if (!ScalarList(x, &g.values))
            pr->Add(path + "." + key, "must be a non-empty list of values" + Line(x));
          b.grid.push_back(std::move(g));
        }
      }
      continue;
    }
    if (k == "set") {
      std::vector<std::string> items;
      bool ok = v.kind == YamlNode::Kind::kSequence && ScalarList(v, &items);
      for (const auto& o : items) ok = ok && o.find('=') != std::string::npos;
      if (!ok && !(v.kind == YamlNode::Kind::kSequence && v.items.empty()))
        pr->Add(path, "must be a list of key=value overrides" + Line(v));
      else
        b.base = items;
      continue;
    }
    if (v.kind != YamlNode::Kind::kScalar) {
      pr->Add(path, "must be a single value" + Line(v));
      continue;
    }
    long long n = 0;
    if (k == "name") {
      b.name = v.text;
    } else if (k == "file") {
      b.file = v.text;
    } else if (k == "count") {
      if (!params::ParseInt(v.text, &n) || n < 1 ||
          n > static_cast<long long>(kMaxMonteCarloScenarios))
        pr->Add(path, "must be a whole number in [1, " + std::to_string(kMaxMonteCarloScenarios) +
                          "], got '" + v.text + "'" + Line(v));
      else
        b.count = static_cast<int>(n);
    } else if (k == "seed") {
      if (!params::ParseInt(v.text, &n) || n < 0)
        pr->Add(path, "must be a whole number >= 0, got '" + v.text + "'" + Line(v));
      else
        b.seed = static_cast<std::uint64_t>(n);
    } else if (k == "weight") {
      if (!params::ParseDouble(v.text, &b.weight) || !std::isfinite(b.weight) || b.weight < 0)
        pr->Add(path, "must be a finite number >= 0, got '" + v.text + "'" + Line(v));
    } else {
      pr->Add(path,
              "unknown key (expected name, count, seed, weight, file, set, vary, grid)" + Line(v));
    }
  }
  if (b.name.empty()) pr->Add(where + ".name", "required key is missing" + line);
  if (b.Size() > kMaxMonteCarloScenarios)
    pr->Add(where, "expands to more than " + std::to_string(kMaxMonteCarloScenarios) +
                       " scenarios (count × grid sizes)" + line);
  return b;
}

}  // namespace scw::tuning
