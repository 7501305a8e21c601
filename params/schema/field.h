// Parameter schema vocabulary: every parameter struct of the workspace describes each of its fields
// exactly once, with the metadata below, in a static `Visit` function. Loading, saving, validation,
// the docs table, the ROS 2 export and the tuner's search space are all derived from that single
// description (STYLE.md §4).
//
// A parameter struct `P` provides
//
//   template <class Self, class V> static void Visit(Self& self, V& v);   // Self = P or const P
//
// which calls, in file order,
//   v.Field(self.member, Meta{...});            // member: double, int, bool, std::vector<double>,
//                                               //         std::string
//   v.Nested("key", self.sub_struct);           // a nested map (its own Visit), dotted path "key."
//   v.List(self.entries, Meta{...});            // a list of maps: std::vector<E>, E with its own
//                                               // Visit; element i has the path "key[i]."
// and optionally
//   static void CrossCheck(const P& p, Problems& problems);    // rules between fields
//
// Header-only and dependency-free so that controller/ and plant/ can use parameter structs
// without linking yaml-cpp (the YAML I/O lives in params/io).
#pragma once

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace scw {

/// One violated rule: the dotted key path and a sentence naming the rule.
struct Problem {
  std::string path;
  std::string message;
};

/// Collects every problem of a configuration before anything throws.
class Problems {
 public:
  void Add(std::string path, std::string message) {
    items_.push_back({std::move(path), std::move(message)});
  }
  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const std::vector<Problem>& items() const { return items_; }
  void Append(const Problems& other) {
    items_.insert(items_.end(), other.items_.begin(), other.items_.end());
  }

 private:
  std::vector<Problem> items_;
};

/// Thrown at configuration time only, never inside a simulation step. `what()` lists every problem
/// as `file: key.path: rule`, one per line.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, std::vector<Problem> problems)
      : std::runtime_error(Format(file, problems)),
        file_(std::move(file)),
        problems_(std::move(problems)) {}
  ConfigError(std::string file, std::string path, std::string message)
      : ConfigError(std::move(file), {Problem{std::move(path), std::move(message)}}) {}

  const std::string& file() const { return file_; }
  const std::vector<Problem>& problems() const { return problems_; }

  static std::string Format(const std::string& file, const std::vector<Problem>& problems) {
    std::ostringstream out;
    for (std::size_t i = 0; i < problems.size(); ++i) {
      if (i) out << '\n';
      out << (file.empty() ? std::string("<input>") : file) << ": ";
      if (!problems[i].path.empty()) out << problems[i].path << ": ";
      out << problems[i].message;
    }
    return out.str();
  }

 private:
  std::string file_;
  std::vector<Problem> problems_;
};

namespace params {

/// How the tuner may move a parameter (and whether it may at all).
enum class Scale {
  kFixed,   ///< structural, physical or safety parameter: never tuned
  kLinear,  ///< tuned on a linear scale within [lo, hi]
  kLog,     ///< tuned on a log10 scale within [lo, hi] (requires lo > 0)
};

/// Metadata of one field. `key` is relative to the enclosing struct (may itself contain dots).
struct Meta {
  std::string_view key;
  std::string_view unit = "-";
  double lo = -std::numeric_limits<double>::infinity();  ///< inclusive lower bound (each element)
  double hi = std::numeric_limits<double>::infinity();   ///< inclusive upper bound (each element)
  std::string_view doc = "";
  Scale scale = Scale::kFixed;
  /// Tunable fields (scale not kFixed): the smallest change that matters on the car, in `unit`
  /// (e.g. 0.001 rad, 0.01 bar, 0.1 % slip); 0 = none. A tuned value is exported as a multiple of
  /// it (RoundToResolution), and a tuned value within one step of the base value as the base value
  /// itself, so the overrides file lists only real changes (tuning/optim/space.h).
  double resolution = 0.0;
  bool optional = false;          ///< may be absent from a file; the in-class default is then kept
  int min_size = 1;               ///< arrays and lists: minimum number of elements
  bool ascending = false;         ///< arrays: strictly ascending elements required
  std::string_view choices = "";  ///< strings: '|'-separated list of allowed values (empty: any)
  /// Accepted by the workspace but not declared by the car's node (the node ignores the key).
  bool workspace_only = false;
  /// Plain workspace files: the writer leaves the field out while it holds its in-class default
  /// (a list entry's `transform: direct`); the loader then restores that default (needs optional).
  bool omit_default = false;
};

/// True for the value type of `v.List`: a vector of schema structs (std::vector<double> is an
/// array field).
template <class T>
inline constexpr bool kIsList = false;
template <class E>
inline constexpr bool kIsList<std::vector<E>> =
    std::is_class_v<E> && !std::is_same_v<E, std::string>;

/// Path of element `i` of the list at `path`: "parameters[3]".
inline std::string ListItemPath(std::string_view path, std::size_t i) {
  return std::string(path) + "[" + std::to_string(i) + "]";
}

/// Metadata of one output field: a quantity a model or run reports (a result, not a parameter: no
/// bounds, no default, never tuned). An output struct `O` lists each member once in
///
///   template <class Self, class V> static void Visit(Self& self, V& v);   // Self = O or const O
///
/// calling `v.Output(self.member, OutputMeta{...})`, and every rendering (text, YAML, CSV columns,
/// the exact wire encoding between processes) is derived from that list.
struct OutputMeta {
  /// The name every rendering uses (YAML key, CSV column), with the rendered unit as its suffix
  /// (`time_s`, `max_abs_sideslip_deg`).
  std::string_view key;
  std::string_view unit = "-";  ///< unit of the rendered value
  std::string_view doc = "";
  /// The member holds radians and renderings show degrees: rendered = member · 180 / π.
  bool rad_to_deg = false;
  /// Part of the run summaries; false for internal bookkeeping (still in the exact encoding).
  bool summary = true;
};

/// The value an output field is rendered with (degrees for radian members).
inline double RenderedValue(double member, const OutputMeta& m) {
  return m.rad_to_deg ? member * 180.0 / M_PI : member;
}

inline std::string JoinKey(std::string_view prefix, std::string_view key) {
  if (prefix.empty()) return std::string(key);
  std::string out(prefix);
  out += '.';
  out += key;
  return out;
}

/// Calls `fn(path, value&, meta)` for every field of `p` (recursing into nested structs) with the
/// full dotted path. Works for const and non-const `p`.
template <class Fn>
class PathVisitor {
 public:
  PathVisitor(Fn& fn, std::string prefix) : fn_(fn), prefix_(std::move(prefix)) {}
  PathVisitor(Fn& fn, std::string prefix, bool optional)
      : fn_(fn), prefix_(std::move(prefix)), optional_(optional) {}
  template <class T>
  void Field(T& value, const Meta& meta) {
    static_assert(!kIsList<std::remove_const_t<T>>, "a list of structs is declared with v.List");
    Call(value, meta);
  }
  /// The whole list is passed to `fn` (value: std::vector<E>); its elements are not expanded
  /// (their number is only known to the caller: the loader, the writer, the validator).
  template <class E>
  void List(E& list, const Meta& meta) {
    static_assert(kIsList<std::remove_const_t<E>>, "v.List takes a std::vector of schema structs");
    Call(list, meta);
  }
  /// `optional`: the whole group may be absent (all its fields become optional).
  template <class S>
  void Nested(std::string_view key, S& sub, bool optional = false) {
    PathVisitor inner(fn_, JoinKey(prefix_, key), optional_ || optional);
    std::remove_const_t<S>::Visit(sub, inner);
  }

 private:
  template <class T>
  void Call(T& value, const Meta& meta) {
    if (optional_ && !meta.optional) {
      Meta m = meta;
      m.optional = true;
      fn_(JoinKey(prefix_, meta.key), value, m);
    } else {
      fn_(JoinKey(prefix_, meta.key), value, meta);
    }
  }

  Fn& fn_;
  std::string prefix_;
  bool optional_ = false;
};

template <class P, class Fn>
void ForEachField(P& p, Fn&& fn, std::string prefix = "") {
  PathVisitor<std::remove_reference_t<Fn>> v(fn, std::move(prefix));
  std::remove_const_t<P>::Visit(p, v);
}

template <class P>
concept HasCrossCheck = requires(const P& p, Problems& pr) {
  P::CrossCheck(p, pr);
};

/// Shortest text that reads back to exactly `x` (locale-independent).
inline std::string FormatNumber(double x) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof(buf), x);
  return std::string(buf, res.ptr);
}

/// The value `steps` × r of a resolution grid, computed so that its shortest text is the decimal
/// one: for r = 1/k (0.1, 0.001, 0.05 …) as steps / k, a single correctly rounded division
/// (3 × 0.1 = 0.30000000000000004, 3 / 10 = 0.3); otherwise (r = 1, 10, 2.5 …) as steps × r, exact
/// for whole numbers of steps.
inline double ResolutionGridValue(double steps, double r) {
  const double k = std::round(1.0 / r);
  const double v = r < 1.0 && k >= 2.0 && std::abs(k * r - 1.0) < 1e-12 ? steps / k : steps * r;
  return v + 0.0;  // no -0.0
}

/// x / r for the grid of ResolutionGridValue (x · k for r = 1/k: one rounding instead of two).
inline double ResolutionSteps(double x, double r) {
  const double k = std::round(1.0 / r);
  return r < 1.0 && k >= 2.0 && std::abs(k * r - 1.0) < 1e-12 ? x * k : x / r;
}

/// The multiple of `r` nearest to `x` (halves away from zero); `x` itself when r <= 0 or x is not
/// finite. RoundToResolution(0.6000000000000002, 0.001) == 0.6.
inline double RoundToResolution(double x, double r) {
  if (!(r > 0.0) || !std::isfinite(x)) return x;
  return ResolutionGridValue(std::round(ResolutionSteps(x, r)), r);
}

namespace detail {
inline void CheckScalar(const std::string& path, double x, const Meta& m, Problems& pr,
                        const std::string& what) {
  if (!std::isfinite(x)) {
    pr.Add(path, what + " must be finite");
    return;
  }
  if (x < m.lo)
    pr.Add(path, what + FormatNumber(x) + " is below the lower bound " + FormatNumber(m.lo));
  else if (x > m.hi)
    pr.Add(path, what + FormatNumber(x) + " is above the upper bound " + FormatNumber(m.hi));
}
}  // namespace detail

namespace detail {
class ValidateVisitor {
 public:
  ValidateVisitor(Problems& pr, std::string prefix) : pr_(pr), prefix_(std::move(prefix)) {}

  void Field(const double& value, const Meta& m) { CheckScalar(Path(m), value, m, pr_, ""); }
  void Field(const int& value, const Meta& m) {
    CheckScalar(Path(m), static_cast<double>(value), m, pr_, "");
  }
  void Field(const bool&, const Meta&) {}
  void Field(const std::vector<double>& value, const Meta& m) {
    const std::string path = Path(m);
    if (static_cast<int>(value.size()) < m.min_size)
      pr_.Add(path, "needs at least " + std::to_string(m.min_size) + " element(s), has " +
                        std::to_string(value.size()));
    for (std::size_t i = 0; i < value.size(); ++i)
      CheckScalar(path, value[i], m, pr_, "element [" + std::to_string(i) + "] = ");
    if (m.ascending)
      for (std::size_t i = 1; i < value.size(); ++i)
        if (!(value[i] > value[i - 1])) {
          pr_.Add(path, "elements must be strictly ascending (element [" + std::to_string(i) +
                            "] is not above element [" + std::to_string(i - 1) + "])");
          break;
        }
  }
  void Field(const std::string& value, const Meta& m) {
    if (m.choices.empty()) return;
    std::string_view rest = m.choices;
    while (true) {
      auto bar = rest.find('|');
      if (rest.substr(0, bar) == value) return;
      if (bar == std::string_view::npos) break;
      rest.remove_prefix(bar + 1);
    }
    pr_.Add(Path(m), "'" + value + "' is not one of " + std::string(m.choices));
  }
  template <class S>
  void Nested(std::string_view key, const S& sub, bool optional = false);
  template <class E>
  void List(const std::vector<E>& list, const Meta& m);

 private:
  std::string Path(const Meta& m) const { return JoinKey(prefix_, m.key); }
  Problems& pr_;
  std::string prefix_;
};
}  // namespace detail

/// Checks every field against its bounds (and array rules), then the cross-field rules of the
/// struct and of every nested struct. Paths are prefixed with `prefix`.
template <class P>
Problems Validate(const P& p, const std::string& prefix = "") {
  Problems pr;
  detail::ValidateVisitor v(pr, prefix);
  P::Visit(p, v);
  if constexpr (HasCrossCheck<P>) {
    Problems cross;
    P::CrossCheck(p, cross);
    for (const auto& c : cross.items()) pr.Add(JoinKey(prefix, c.path), c.message);
  }
  return pr;
}

template <class S>
void detail::ValidateVisitor::Nested(std::string_view key, const S& sub, bool /*optional*/) {
  pr_.Append(Validate(sub, JoinKey(prefix_, key)));
}

template <class E>
void detail::ValidateVisitor::List(const std::vector<E>& list, const Meta& m) {
  const std::string path = Path(m);
  if (static_cast<int>(list.size()) < m.min_size)
    pr_.Add(path, "needs at least " + std::to_string(m.min_size) + " entr" +
                      (m.min_size == 1 ? "y" : "ies") + ", has " + std::to_string(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i)
    pr_.Append(Validate(list[i], ListItemPath(path, i)));
}

/// Throws ConfigError listing every problem (file name used only for the message).
template <class P>
void ValidateOrThrow(const P& p, const std::string& file = "") {
  Problems pr = Validate(p);
  if (!pr.empty()) throw ConfigError(file, pr.items());
}

}  // namespace params
}  // namespace scw
