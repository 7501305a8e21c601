#include "tuning/sim/monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/scenario_params.h"

namespace scw::tuning {
namespace {

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

bool Whole(double x) { return x == std::floor(x) && std::fabs(x) <= 1e15; }

// The value of draw `d` (valid: CrossCheck holds) for the random bits of one scenario and key.
std::string Drawn(const MonteCarloDraw& d, std::uint64_t bits) {
  const double u = Unit(bits);
  if (d.choice) {
    const auto& choices = *d.choice;
    const auto i = std::min(choices.size() - 1, static_cast<std::size_t>(u * choices.size()));
    return choices[i];
  }
  if (d.integer) {
    const double lo = (*d.integer)[0], hi = (*d.integer)[1];
    const double n = hi - lo + 1.0;
    const double v = std::min(hi, lo + std::floor(u * n));
    return std::to_string(static_cast<long long>(v));
  }
  const double lo = (*d.uniform)[0], hi = (*d.uniform)[1];
  double v = lo + u * (hi - lo);
  if (d.step) {
    // A multiple of step; dividing by a whole 1/step gives the double nearest to the decimal
    // (0.85, not 0.8500000000000001 as 17 × 0.05 would).
    const double step = *d.step;
    const double inv = std::round(1.0 / step);
    v = std::fabs(inv * step - 1.0) < 1e-12 ? std::round(v * inv) / inv
                                            : std::round(v / step) * step;
    v = std::clamp(v, lo, hi);
  }
  return params::FormatDouble(v);
}

}  // namespace

std::string CheckScenarioKey(const std::string& key) {
  if (KeyKind(key) >= 0) return "";
  std::vector<std::string> known;
  params::ScenarioParams p;
  params::ForEachField(
      p, [&](const std::string& path, const auto&, const params::Meta&) { known.push_back(path); });
  const std::string hint = params::detail::SuggestKey(key, known);
  return "unknown scenario key '" + key + "'" +
         (hint.empty() ? std::string() : " (did you mean " + hint + "?)");
}

void MonteCarloDraw::CrossCheck(const MonteCarloDraw& d, Problems& pr) {
  const int kinds = d.uniform.has_value() + d.integer.has_value() + d.choice.has_value();
  if (kinds != 1) pr.Add("", "give exactly one of uniform, integer, choice");
  auto range = [&](const std::optional<std::vector<double>>& r, const char* key) {
    if (!r) return false;
    if (r->size() != 2 || !((*r)[0] <= (*r)[1])) {
      pr.Add(key, "must be [low, high] with finite numbers, low <= high");
      return false;
    }
    return true;
  };
  range(d.uniform, "uniform");
  if (range(d.integer, "integer") && !(Whole((*d.integer)[0]) && Whole((*d.integer)[1])))
    pr.Add("integer", "the bounds must be whole numbers (|n| <= 1e15)");
  if (d.step && !(*d.step > 0)) pr.Add("step", "must be a number > 0");
  if (d.step && !d.uniform && kinds == 1) pr.Add("step", "only a uniform draw takes a step");
}

void MonteCarloBlock::CrossCheck(const MonteCarloBlock& b, Problems& pr) {
  if (b.Size() > kMaxMonteCarloScenarios)
    pr.Add("", "expands to more than " + std::to_string(kMaxMonteCarloScenarios) +
                   " scenarios (count × grid sizes)");
}

std::size_t MonteCarloBlock::Size() const {
  std::size_t n = count > 0 ? static_cast<std::size_t>(count) : 0;
  if (grid)
    for (const auto& [key, values] : *grid) {
      if (values.empty()) return 0;
      if (n > kMaxMonteCarloScenarios / values.size()) return kMaxMonteCarloScenarios + 1;
      n *= values.size();
    }
  return n;
}

std::string MonteCarloBlock::ScenarioName(std::size_t i) const {
  const std::size_t n = Size();
  const std::size_t width = std::max<std::size_t>(3, std::to_string(n > 0 ? n - 1 : 0).size());
  const std::string index = std::to_string(i);
  return name + "_" + std::string(width - std::min(width, index.size()), '0') + index;
}

std::vector<ScenarioEntry> MonteCarloBlock::Expand() const {
  std::vector<ScenarioEntry> out;
  if (!params::Validate(*this).empty()) return out;
  const std::size_t n = Size();
  static const params::OrderedMap<MonteCarloDraw> kNoDraws;
  static const params::OrderedMap<std::vector<std::string>> kNoGrid;
  const auto& draws = vary ? *vary : kNoDraws;
  const auto& axes = grid ? *grid : kNoGrid;
  std::vector<int> list_key(draws.size() + axes.size());
  for (std::size_t k = 0; k < draws.size(); ++k) list_key[k] = KeyKind(draws[k].first);
  for (std::size_t k = 0; k < axes.size(); ++k) list_key[draws.size() + k] = KeyKind(axes[k].first);
  auto put = [&](ScenarioEntry* e, std::size_t k, const std::string& key, const std::string& v) {
    const bool wrap = list_key[k] == 1 && (v.empty() || v.front() != '[');
    e->overrides.push_back(key + "=" + (wrap ? "[" + v + "]" : v));
  };
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    ScenarioEntry e;
    e.name = ScenarioName(i);
    e.weight = weight;
    e.file = file;
    e.overrides = base;
    // Grid point: i / count, first grid key slowest.
    std::size_t point = i / static_cast<std::size_t>(count);
    std::vector<std::size_t> at(axes.size());
    for (std::size_t k = axes.size(); k-- > 0;) {
      at[k] = point % axes[k].second.size();
      point /= axes[k].second.size();
    }
    for (std::size_t k = 0; k < axes.size(); ++k)
      put(&e, draws.size() + k, axes[k].first, axes[k].second[at[k]]);
    // Draws: a stream per scenario index, one number per key in the order written.
    std::uint64_t state =
        Mix(static_cast<std::uint64_t>(seed) ^ Mix(static_cast<std::uint64_t>(i)));
    for (std::size_t k = 0; k < draws.size(); ++k) {
      state = Mix(state);
      put(&e, k, draws[k].first, Drawn(draws[k].second, state));
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace scw::tuning
