#include "tuning/optim/space.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

#include "params/io/load.h"
#include "params/io/stability_lint.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/optim/default_space_yaml.h"  // generated: generated::kDefaultSpaceYaml

namespace scw::tuning {
namespace {

using params::Meta;
using params::Scale;
using params::StabilityParams;

struct FieldRef {
  double* scalar = nullptr;
  std::vector<double>* array = nullptr;
  Meta meta;
};

/// Pointers to every double / double[] field of p by dotted key.
std::map<std::string, FieldRef> Fields(StabilityParams& p) {
  std::map<std::string, FieldRef> out;
  params::ForEachField(p, [&](const std::string& path, auto& value, const Meta& m) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_same_v<T, double>) out[path] = {&value, nullptr, m};
    if constexpr (std::is_same_v<T, std::vector<double>>) out[path] = {nullptr, &value, m};
  });
  return out;
}

double ToX(const SpaceEntry& e, double u) {
  u = std::clamp(std::isfinite(u) ? u : 0.5, 0.0, 1.0);
  if (e.scale == Scale::kLog) return e.lo * std::pow(e.hi / e.lo, u);
  return e.lo + u * (e.hi - e.lo);
}

double ToU(const SpaceEntry& e, double x) {
  double u = 0.5;
  if (e.scale == Scale::kLog)
    u = x > 0 ? std::log(x / e.lo) / std::log(e.hi / e.lo) : 0.0;
  else
    u = (x - e.lo) / (e.hi - e.lo);
  return std::clamp(std::isfinite(u) ? u : 0.5, 0.0, 1.0);
}

const char* TransformName(Transform t) {
  switch (t) {
    case Transform::kDirect:
      return "direct";
    case Transform::kOffset:
      return "offset";
    case Transform::kRatio:
      return "ratio";
    case Transform::kScaleArray:
      return "scale_array";
  }
  return "?";
}

// "ESC.x[1]" → ("ESC.x", 1)
std::pair<std::string, int> SplitIndex(const std::string& key) {
  const auto open = key.find('[');
  if (open == std::string::npos || key.back() != ']') return {key, -1};
  long long i = -1;
  if (!params::ParseInt(key.substr(open + 1, key.size() - open - 2), &i) || i < 0) return {key, -2};
  return {key.substr(0, open), static_cast<int>(i)};
}

double RefValue(const FieldRef& f, int index) {
  if (f.scalar) return *f.scalar;
  if (index >= static_cast<int>(f.array->size()) || f.array->empty())
    return std::numeric_limits<double>::quiet_NaN();  // a base with a shorter array
  if (index >= 0) return (*f.array)[static_cast<std::size_t>(index)];
  return *std::min_element(f.array->begin(), f.array->end());
}

// The reference of a ratio in `set` (whose fields are `fields`): one element, a scalar, or for a
// whole array its smallest value — for a velocity-scheduled ESC threshold the smallest value the
// car's node interpolates at the speeds where it checks the hysteresis (params::ScheduledMinimum),
// so that a fraction below 1 keeps the deactivation threshold below the activation threshold at
// every speed; the smallest element where that schedule is not positive.
double RatioRef(const SpaceEntry& e, const std::map<std::string, FieldRef>& fields,
                const StabilityParams& set) {
  const FieldRef& f = fields.at(e.of);
  if (e.of_index < 0 && f.array) {
    const double scheduled = params::ScheduledMinimum(set, e.of);
    if (std::isfinite(scheduled)) return scheduled;
  }
  return RefValue(f, e.of_index);
}

// The transform argument x that reproduces the target value of `e` in the set behind `fields`
// (references taken from the same set). NaN: no x can (a ratio of a zero reference).
double ArgumentOf(const SpaceEntry& e, std::map<std::string, FieldRef>& fields,
                  const StabilityParams& set) {
  const FieldRef& f = fields.at(e.key);
  if (e.transform == Transform::kScaleArray) return 1.0;  // the base array itself
  const double v = RefValue(f, e.index);
  switch (e.transform) {
    case Transform::kDirect:
      return v;
    case Transform::kOffset:
      return v - RefValue(fields.at(e.of), e.of_index);
    case Transform::kRatio: {
      const double r = RatioRef(e, fields, set);
      if (r != 0) return v / r;
      return v == 0 ? std::clamp(1.0, e.lo, e.hi) : std::numeric_limits<double>::quiet_NaN();
    }
    case Transform::kScaleArray:
      break;
  }
  return 1.0;
}

bool InSchema(double v, const Meta& m) { return v >= m.lo && v <= m.hi; }

// The value written for a tuned `raw` value whose base value is `base`: the base value when within
// one resolution step, else the nearest multiple of the resolution, else the other neighbouring
// multiple — the first that `ok` accepts (the entry's range and the schema bounds); `raw` when none
// is (never for sensible resolutions) or the field has no resolution.
template <class Ok>
double Quantize(double raw, double base, double res, const Ok& ok) {
  if (!(res > 0) || !std::isfinite(raw)) return raw;
  if (std::abs(raw - base) < res && ok(base)) return base;
  const double steps = params::ResolutionSteps(raw, res);
  const double n = std::round(steps);
  const double nearest = params::ResolutionGridValue(n, res);
  if (ok(nearest)) return nearest;
  const double other = params::ResolutionGridValue(n + (steps >= n ? 1.0 : -1.0), res);
  if (ok(other)) return other;
  return raw;
}

// x rounded away from the inside of a range to 3 significant digits (up: towards +inf).
double Outward(double x, bool up) {
  if (x == 0 || !std::isfinite(x)) return x;
  const int e = static_cast<int>(std::floor(std::log10(std::abs(x)))) - 2;
  double v = x;
  if (e < 0) {
    const double k = std::pow(10.0, -e);
    v = (up ? std::ceil(x * k) : std::floor(x * k)) / k;
  } else {
    const double k = std::pow(10.0, e);
    v = (up ? std::ceil(x / k) : std::floor(x / k)) * k;
  }
  return (up ? v >= x : v <= x) ? v : x;
}

std::string Short(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.4g", x);
  return buf;
}

}  // namespace

std::string SpaceEntry::Label() const {
  return index >= 0 ? key + "[" + std::to_string(index) + "]" : key;
}

ParameterSpace::ParameterSpace(std::string name, std::vector<SpaceEntry> entries)
    : name_(std::move(name)), entries_(std::move(entries)) {
  Problems pr;
  StabilityParams base;
  auto fields = Fields(base);
  std::map<std::string, int> seen;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const SpaceEntry& e = entries_[i];
    const std::string at = "parameters[" + std::to_string(i) + "]";
    auto it = fields.find(e.key);
    if (it == fields.end()) {
      pr.Add(at + ".key", "'" + e.key + "' is not a double or double-array stability parameter");
      continue;
    }
    const FieldRef& f = it->second;
    if (!(e.lo < e.hi)) pr.Add(at, "lo must be below hi");
    if (e.scale == Scale::kLog && !(e.lo > 0)) pr.Add(at + ".lo", "log scale needs lo > 0");
    if (e.scale == Scale::kFixed) pr.Add(at + ".scale", "must be linear or log");
    if (seen.count(e.Label()))
      pr.Add(at + ".key", "'" + e.Label() + "' is tuned twice (also parameters[" +
                              std::to_string(seen[e.Label()]) + "])");
    seen[e.Label()] = static_cast<int>(i);
    switch (e.transform) {
      case Transform::kDirect:
        if (f.array && e.index < 0)
          pr.Add(at + ".key",
                 "an array parameter needs an element index key[i] or "
                 "transform: scale_array");
        if (f.array && e.index >= static_cast<int>(f.array->size()))
          pr.Add(at + ".key", "element index out of range");
        if (e.lo < f.meta.lo || e.hi > f.meta.hi)
          pr.Add(at, "bounds [" + params::FormatNumber(e.lo) + ", " + params::FormatNumber(e.hi) +
                         "] must lie within the schema bounds [" + params::FormatNumber(f.meta.lo) +
                         ", " + params::FormatNumber(f.meta.hi) + "] of " + e.key);
        break;
      case Transform::kScaleArray:
        if (!f.array) pr.Add(at + ".transform", "scale_array needs an array parameter");
        if (!(e.lo > 0)) pr.Add(at + ".lo", "scale factors must be positive");
        break;
      case Transform::kOffset:
      case Transform::kRatio: {
        if (f.array && e.index < 0)
          pr.Add(at + ".key", "offset/ratio apply to a scalar or one element key[i]");
        if (f.array && e.index >= static_cast<int>(f.array->size()))
          pr.Add(at + ".key", "element index out of range");
        auto ref = fields.find(e.of);
        if (e.of.empty() || ref == fields.end())
          pr.Add(at + ".of", "'" + e.of + "' is not a double or double-array parameter");
        else if (ref->second.array && e.of_index >= static_cast<int>(ref->second.array->size()))
          pr.Add(at + ".of", "element index out of range");
        if (e.of == e.key && e.of_index == e.index) pr.Add(at + ".of", "refers to itself");
        break;
      }
    }
  }
  if (!pr.empty()) throw ConfigError(name_, pr.items());
}

StabilityParams ParameterSpace::Decode(const std::vector<double>& u, const StabilityParams& base,
                                       Problems* problems) const {
  StabilityParams p = base;
  auto fields = Fields(p);
  StabilityParams base_copy = base;
  auto base_fields = Fields(base_copy);
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const SpaceEntry& e = entries_[i];
    const double ui = i < u.size() ? u[i] : 0.5;
    FieldRef& f = fields.at(e.key);
    const FieldRef& bf = base_fields.at(e.key);
    if (f.array && e.index >= static_cast<int>(f.array->size())) {
      if (problems)
        problems->Add(e.Label(), "the base set's array has only " +
                                     std::to_string(f.array->size()) + " elements");
      continue;
    }
    const bool relative = e.transform == Transform::kOffset || e.transform == Transform::kRatio;
    const auto reference = [&](const std::map<std::string, FieldRef>& fs,
                               const StabilityParams& set) {
      if (e.transform == Transform::kRatio) return RatioRef(e, fs, set);
      return relative ? RefValue(fs.at(e.of), e.of_index) : 0.0;
    };
    const double ref = reference(fields, p);

    // Pinned: the base value, or where a moved reference leaves it outside the range, the value
    // nearest to it that keeps the entry's relation.
    if (e.pinned) {
      const auto copy_base = [&] {
        if (e.transform == Transform::kScaleArray)
          *f.array = *bf.array;
        else if (f.array)
          (*f.array)[static_cast<std::size_t>(e.index)] =
              (*bf.array)[static_cast<std::size_t>(e.index)];
        else
          *f.scalar = *bf.scalar;
      };
      if (!relative) {
        copy_base();
        continue;
      }
      double* slot = f.array ? &(*f.array)[static_cast<std::size_t>(e.index)] : f.scalar;
      const double b = f.array ? (*bf.array)[static_cast<std::size_t>(e.index)] : *bf.scalar;
      double x_b = e.transform == Transform::kOffset ? b - ref : (ref != 0 ? b / ref : NAN);
      if (!std::isfinite(x_b) || (x_b >= e.lo && x_b <= e.hi)) {
        copy_base();
        continue;
      }
      const double x = std::clamp(x_b, e.lo, e.hi);
      const double raw = e.transform == Transform::kOffset ? ref + x : ref * x;
      *slot = Quantize(raw, b, f.meta.resolution, [&](double v) {
        if (!InSchema(v, f.meta)) return false;
        const double a = e.transform == Transform::kOffset ? v - ref : v / ref;
        return a >= e.lo && a <= e.hi;
      });
      continue;
    }

    // At the base's own coordinate with the reference unchanged: the base value, bit for bit.
    const double xb = ArgumentOf(e, base_fields, base_copy);
    if (std::isfinite(xb) && xb >= e.lo && xb <= e.hi && ui == ToU(e, xb) &&
        (!relative || ref == reference(base_fields, base_copy))) {
      if (e.transform == Transform::kScaleArray)
        *f.array = *bf.array;
      else if (f.array)
        (*f.array)[static_cast<std::size_t>(e.index)] =
            (*bf.array)[static_cast<std::size_t>(e.index)];
      else
        *f.scalar = *bf.scalar;
      continue;
    }

    const double x = ToX(e, ui);
    const double res = f.meta.resolution;
    if (e.transform == Transform::kScaleArray) {
      // Scale the BASE array so the factor keeps its meaning whatever was decoded before.
      const auto& src = *bf.array;
      for (std::size_t j = 0; j < f.array->size() && j < src.size(); ++j)
        (*f.array)[j] =
            Quantize(src[j] * x, src[j], res, [&](double v) { return InSchema(v, f.meta); });
      continue;
    }
    double* target = f.scalar;
    double b = bf.scalar ? *bf.scalar : 0.0;
    if (f.array) {
      target = &(*f.array)[static_cast<std::size_t>(e.index)];
      b = (*bf.array)[static_cast<std::size_t>(e.index)];
    }
    // The quantised value must keep the transform's argument within the range (orderings and
    // hysteresis stay valid) and the value within the schema bounds.
    auto ok = [&](double v) {
      if (!InSchema(v, f.meta)) return false;
      double a = v;
      if (e.transform == Transform::kOffset) a = v - ref;
      if (e.transform == Transform::kRatio) {
        if (ref == 0) return true;
        a = v / ref;
      }
      return a >= e.lo && a <= e.hi;
    };
    double raw = x;
    if (e.transform == Transform::kOffset) raw = ref + x;
    if (e.transform == Transform::kRatio) raw = ref * x;
    *target = Quantize(raw, b, res, ok);
  }
  if (problems) *problems = params::Validate(p);
  return p;
}

ParameterSpace ParameterSpace::WithPinned(const std::vector<int>& dims) const {
  ParameterSpace out = *this;
  for (int i : dims)
    if (i >= 0 && i < size()) out.entries_[static_cast<std::size_t>(i)].pinned = true;
  return out;
}

std::vector<double> ParameterSpace::Arguments(const std::vector<double>& u) const {
  std::vector<double> x(entries_.size());
  for (std::size_t i = 0; i < entries_.size(); ++i)
    x[i] = ToX(entries_[i], i < u.size() ? u[i] : 0.5);
  return x;
}

std::vector<double> ParameterSpace::Encode(const StabilityParams& p_in) const {
  StabilityParams p = p_in;
  auto fields = Fields(p);
  std::vector<double> u(entries_.size(), 0.5);
  for (std::size_t i = 0; i < entries_.size(); ++i)
    u[i] = ToU(entries_[i], ArgumentOf(entries_[i], fields, p));
  return u;
}

std::vector<BaseMismatch> ParameterSpace::BaseMismatches(const StabilityParams& base) const {
  StabilityParams p = base;
  auto fields = Fields(p);
  std::vector<BaseMismatch> out;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const SpaceEntry& e = entries_[i];
    const double xb = ArgumentOf(e, fields, p);
    const bool log_bad = e.scale == Scale::kLog && !(xb > 0);
    if (std::isfinite(xb) && !log_bad && xb >= e.lo && xb <= e.hi) continue;
    BaseMismatch m;
    m.index = static_cast<int>(i);
    m.label = e.Label();
    m.x_base = xb;
    m.lo = e.lo;
    m.hi = e.hi;
    const std::string range =
        "[" + params::FormatNumber(e.lo) + ", " + params::FormatNumber(e.hi) + "]";
    const FieldRef& f = fields.at(e.key);
    const std::string value = e.transform == Transform::kScaleArray
                                  ? params::FormatDoubleList(*f.array)
                                  : params::FormatNumber(RefValue(f, e.index));
    std::string of = e.of_index >= 0 ? e.of + "[" + std::to_string(e.of_index) + "]" : e.of;
    if (!e.of.empty() && e.of_index < 0 && fields.at(e.of).array)
      of =
          (std::isfinite(params::ScheduledMinimum(p, e.of)) ? "scheduled_min(" : "min(") + of + ")";
    switch (e.transform) {
      case Transform::kDirect:
        m.message = "the base value " + value + " lies outside the range " + range;
        break;
      case Transform::kOffset:
        m.message = "the base value " + value + " is " + of + " + " + Short(xb) +
                    ", outside the offset range " + range;
        break;
      case Transform::kRatio:
        m.message = std::isfinite(xb)
                        ? "the base value " + value + " is " + Short(xb) + " × " + of +
                              ", outside the ratio range " + range
                        : "the base value " + value + " is not a multiple of " + of + " = 0";
        break;
      case Transform::kScaleArray:
        m.message = "the base array itself (factor 1) lies outside the scale range " + range;
        break;
    }
    if (!std::isfinite(xb) || log_bad) {
      m.representable = false;
      if (log_bad && std::isfinite(xb)) m.message += " (the log scale needs a positive argument)";
      m.grown_lo = e.lo;
      m.grown_hi = e.hi;
    } else {
      m.grown_lo = std::min(e.lo, Outward(xb, false));
      m.grown_hi = std::max(e.hi, Outward(xb, true));
      if (e.transform == Transform::kDirect) {  // stay within the schema bounds
        m.grown_lo = std::max(m.grown_lo, f.meta.lo);
        m.grown_hi = std::min(m.grown_hi, f.meta.hi);
      }
    }
    out.push_back(m);
  }
  return out;
}

ParameterSpace ParameterSpace::WithBase(const StabilityParams& base, BaseOutsideSpace policy,
                                        std::vector<std::string>* notes) const {
  const auto mismatches = BaseMismatches(base);
  Problems pr;
  for (const auto& m : mismatches) {
    if (!m.representable)
      pr.Add(m.label, m.message +
                          "; no range can represent it: remove the entry from the space or change "
                          "the base value");
    else if (policy == BaseOutsideSpace::kRefuse)
      pr.Add(m.label, m.message + "; widen the range to [" + params::FormatNumber(m.grown_lo) +
                          ", " + params::FormatNumber(m.grown_hi) +
                          "] in the space file (or let scw tune grow it: --base-outside grow)");
  }
  if (!pr.empty()) throw ConfigError(name_, pr.items());
  if (mismatches.empty()) return *this;
  std::vector<SpaceEntry> entries = entries_;
  for (const auto& m : mismatches) {
    SpaceEntry& e = entries[static_cast<std::size_t>(m.index)];
    e.lo = m.grown_lo;
    e.hi = m.grown_hi;
    if (notes)
      notes->push_back(m.label + ": " + m.message + "; range grown to [" +
                       params::FormatNumber(m.grown_lo) + ", " + params::FormatNumber(m.grown_hi) +
                       "] so that the base set is exactly representable");
  }
  return ParameterSpace(name_, std::move(entries));
}

SpaceFile ParameterSpace::ToFile() const {
  SpaceFile f;
  f.name = name_;
  for (const auto& e : entries_) {
    SpaceFileEntry& fe = f.parameters.emplace_back();
    fe.key = e.Label();
    fe.transform = TransformName(e.transform);
    fe.of = e.of_index >= 0 ? e.of + "[" + std::to_string(e.of_index) + "]" : e.of;
    fe.lo = e.lo;
    fe.hi = e.hi;
    fe.scale = e.scale == Scale::kLog ? "log" : "linear";
  }
  return f;
}

std::string ParameterSpace::ToYaml() const { return params::ToPlainYaml(ToFile()); }

ParameterSpace ParameterSpace::FromYamlText(const std::string& text, const std::string& file) {
  params::LoadOptions opt;
  opt.layout = params::Layout::kPlain;
  opt.int_for_double = true;
  params::LoadReport report;
  const SpaceFile f = params::LoadFromText<SpaceFile>(text, file, opt, &report);
  // The text → SpaceEntry step: key[i] and the names of the transforms and scales.
  Problems pr;
  std::vector<SpaceEntry> entries;
  for (std::size_t i = 0; i < f.parameters.size(); ++i) {
    const SpaceFileEntry& fe = f.parameters[i];
    const std::string at = params::ListItemPath("parameters", i);
    auto split = [&](const std::string& field, const std::string& value, std::string* key,
                     int* index) {
      std::tie(*key, *index) = SplitIndex(value);
      if (*index != -2) return;
      const auto line = report.lines.find(at + "." + field);
      pr.Add(at + "." + field,
             "bad element index in '" + value + "' (expected key or key[i], i >= 0)" +
                 params::detail::LineSuffix(line == report.lines.end() ? 0 : line->second));
    };
    SpaceEntry& e = entries.emplace_back();
    split("key", fe.key, &e.key, &e.index);
    split("of", fe.of, &e.of, &e.of_index);
    e.lo = fe.lo;
    e.hi = fe.hi;
    e.scale = fe.scale == "log" ? Scale::kLog : Scale::kLinear;
    for (Transform t :
         {Transform::kDirect, Transform::kOffset, Transform::kRatio, Transform::kScaleArray})
      if (fe.transform == TransformName(t)) e.transform = t;
  }
  if (!pr.empty()) throw ConfigError(file, pr.items());
  try {
    return ParameterSpace(f.name, std::move(entries));
  } catch (const ConfigError& e) {
    throw ConfigError(file, e.problems());
  }
}

ParameterSpace ParameterSpace::FromFile(const std::string& path) {
  return FromYamlText(params::ReadTextFile(path), path);
}

ParameterSpace ParameterSpace::Default() {
  static const ParameterSpace space =
      FromYamlText(generated::kDefaultSpaceYaml, "params/spaces/default.yaml");
  return space;
}

}  // namespace scw::tuning
