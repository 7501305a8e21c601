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
//   v.Field(self.member, Meta{...});            // member: double, int, std::int64_t, bool,
//                                               //   std::vector<double>, std::string,
//                                               //   std::vector<std::string> (a list of texts,
//                                               //   each checked by Meta::rule)
//   v.Nested("key", self.sub_struct);           // a nested map (its own Visit), dotted path "key."
//   v.List(self.entries, Meta{...});            // a list of maps: std::vector<E>, E with its own
//                                               // Visit; element i has the path "key[i]."
//                                               // E may be std::variant<Plain, Block...>: an
//                                               // entry is a Plain map or a single-key map
//                                               // {block-key: {...}} (see kBlock below)
//   v.Map(self.by_key, Meta{...});              // a map whose keys are data (OrderedMap<V>, in
//                                               // file order): V a struct with its own Visit or
//                                               // a field type above; path "key.<its key>"
// and optionally
//   static void CrossCheck(const P& p, Problems& problems);    // rules between fields
//                                               // (path "" names the struct itself)
//
// A member that may be absent, where absent means something no value does (a draw that is not
// uniform, a cost section not given), is a std::optional of any of the above (including a
// nested struct: `v.Nested("key", self.optional_group)`). It is optional in files, written only
// when present, and when present it is complete: every rule applies to it as to a plain member.
//
// A Block alternative of a variant list entry declares its key and description as
//   static constexpr Meta kBlock{.key = "monte_carlo", .doc = "..."};
// and is written `- {monte_carlo: {...}}`; the entry's path is then "key[i].monte_carlo.".
//
// Header-only and dependency-free so that controller/ and plant/ can use parameter structs
// without linking yaml-cpp (the YAML I/O lives in params/io).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
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

/// A rule on text: a string value, each element of a string list, each key of a map.
struct TextRule {
  std::string_view doc = "";  ///< the rule in a few words, for the docs table: "key=value"
  /// "" when `text` follows the rule, else the broken rule naming the text ("must look like
  /// key=value, got 'laps'").
  std::string (*check)(const std::string& text) = nullptr;
};

inline std::string CheckNotEmpty(const std::string& text) {
  return text.empty() ? "must not be empty" : "";
}
/// A text that must be given as something (a name).
inline constexpr TextRule kNotEmpty{"not empty", &CheckNotEmpty};

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
  int min_size = 1;               ///< arrays, lists, maps (keys): minimum number of elements
  bool ascending = false;         ///< arrays: strictly ascending elements required
  std::string_view choices = "";  ///< strings: '|'-separated list of allowed values (empty: any)
  /// Accepted by the workspace but not declared by the car's node (the node ignores the key).
  bool workspace_only = false;
  /// Plain workspace files: the writer leaves the field out while it holds its in-class default
  /// (a list entry's `transform: direct`); the loader then restores that default (needs optional).
  bool omit_default = false;
  /// Strings: the value; string lists: each element; maps (v.Map): each key.
  TextRule rule = {};
};

/// The value type of `v.Map`: a map whose keys are data (scenario keys), in the order written.
template <class V>
using OrderedMap = std::vector<std::pair<std::string, V>>;

template <class T>
inline constexpr bool kIsOptional = false;
template <class T>
inline constexpr bool kIsOptional<std::optional<T>> = true;

/// The member type without its std::optional.
template <class T>
struct Unoptional {
  using type = T;
};
template <class T>
struct Unoptional<std::optional<T>> {
  using type = T;
};
template <class T>
using UnoptionalT = typename Unoptional<std::remove_cv_t<T>>::type;

template <class T>
inline constexpr bool kIsPair = false;
template <class A, class B>
inline constexpr bool kIsPair<std::pair<A, B>> = true;

template <class T>
inline constexpr bool kIsVariant = false;
template <class... A>
inline constexpr bool kIsVariant<std::variant<A...>> = true;

/// True for the value type of `v.Map` (std::optional removed).
template <class T>
inline constexpr bool kIsMap = false;
template <class V>
inline constexpr bool kIsMap<std::vector<std::pair<std::string, V>>> = true;

template <class T>
inline constexpr bool kIsVector = false;
template <class T>
inline constexpr bool kIsVector<std::vector<T>> = true;

/// A schema struct (with its own Visit), as a map value or a std::optional group: any class type
/// that is not a field type.
template <class T>
inline constexpr bool kIsStruct = std::is_class_v<T> && !std::is_same_v<T, std::string> &&
                                  !kIsVector<T> && !kIsOptional<T> && !kIsVariant<T>;

/// True for the value type of `v.List`: a vector of schema structs (std::vector<double> is an
/// array field).
template <class T>
inline constexpr bool kIsList = false;
template <class E>
inline constexpr bool kIsList<std::vector<E>> =
    std::is_class_v<E> && !std::is_same_v<E, std::string> && !kIsPair<E>;

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
    using U = UnoptionalT<T>;
    static_assert(!kIsList<U>, "a list of structs is declared with v.List");
    static_assert(!kIsMap<U>, "a map is declared with v.Map");
    static_assert(!kIsStruct<U>, "a nested struct is declared with v.Nested");
    Call(value, meta);
  }
  /// The whole list is passed to `fn` (value: std::vector<E>, or a std::optional of it); its
  /// elements are not expanded (their number is only known to the caller: the loader, the writer,
  /// the validator).
  template <class E>
  void List(E& list, const Meta& meta) {
    static_assert(kIsList<UnoptionalT<E>>, "v.List takes a std::vector of schema structs");
    Call(list, meta);
  }
  /// The whole map is passed to `fn` (value: OrderedMap<V>, or a std::optional of it).
  template <class M>
  void Map(M& map, const Meta& meta) {
    static_assert(kIsMap<UnoptionalT<M>>, "v.Map takes an OrderedMap");
    Call(map, meta);
  }
  /// `optional`: the whole group may be absent (all its fields become optional). A std::optional
  /// group is passed to `fn` whole (value: std::optional<S>; meta: its key, optional): when
  /// present it is complete, so its fields keep their own `optional`.
  template <class S>
  void Nested(std::string_view key, S& sub, bool optional = false) {
    if constexpr (kIsOptional<std::remove_const_t<S>>) {
      Call(sub, Meta{.key = key, .optional = true});
    } else {
      PathVisitor inner(fn_, JoinKey(prefix_, key), optional_ || optional);
      std::remove_const_t<S>::Visit(sub, inner);
    }
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
inline void CheckText(const std::string& path, const std::string& text, const Meta& m,
                      Problems& pr) {
  if (!m.rule.check) return;
  const std::string broken = m.rule.check(text);
  if (!broken.empty()) pr.Add(path, broken);
}

inline std::string Plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

class ValidateVisitor {
 public:
  ValidateVisitor(Problems& pr, std::string prefix) : pr_(pr), prefix_(std::move(prefix)) {}

  void Field(const double& value, const Meta& m) { CheckScalar(Path(m), value, m, pr_, ""); }
  void Field(const int& value, const Meta& m) {
    CheckScalar(Path(m), static_cast<double>(value), m, pr_, "");
  }
  void Field(const std::int64_t& value, const Meta& m) {
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
    CheckText(Path(m), value, m, pr_);
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
  /// A list of texts: its size, then the rule of each element (path "key[i]").
  void Field(const std::vector<std::string>& value, const Meta& m) {
    const std::string path = Path(m);
    if (static_cast<int>(value.size()) < m.min_size)
      pr_.Add(path, "needs at least " +
                        Plural(static_cast<std::size_t>(m.min_size), "value", "values") + ", has " +
                        std::to_string(value.size()));
    for (std::size_t i = 0; i < value.size(); ++i)
      CheckText(ListItemPath(path, i), value[i], m, pr_);
  }
  /// Absent: nothing to check; present: as the plain member.
  template <class T>
  void Field(const std::optional<T>& value, const Meta& m) {
    if (value) Field(*value, m);
  }
  template <class S>
  void Nested(std::string_view key, const S& sub, bool optional = false);
  template <class E>
  void List(const std::vector<E>& list, const Meta& m);
  template <class E>
  void List(const std::optional<std::vector<E>>& list, const Meta& m) {
    if (list) List(*list, m);
  }
  template <class V>
  void Map(const OrderedMap<V>& map, const Meta& m);
  template <class V>
  void Map(const std::optional<OrderedMap<V>>& map, const Meta& m) {
    if (map) Map(*map, m);
  }

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
    for (const auto& c : cross.items())
      pr.Add(c.path.empty() ? prefix : JoinKey(prefix, c.path), c.message);
  }
  return pr;
}

/// The path of a list entry's struct: "key[i]" for the plain alternative, "key[i].<block key>"
/// for a block (kBlock) of a variant entry.
template <class A>
std::string EntryPath(const std::string& item_path) {
  if constexpr (requires { A::kBlock; })
    return JoinKey(item_path, A::kBlock.key);
  else
    return item_path;
}

/// Validate for one list entry (a struct, or a variant of structs).
template <class E>
Problems ValidateEntry(const E& e, const std::string& item_path) {
  if constexpr (kIsVariant<E>)
    return std::visit(
        [&](const auto& alt) {
          return Validate(alt, EntryPath<std::decay_t<decltype(alt)>>(item_path));
        },
        e);
  else
    return Validate(e, item_path);
}

template <class S>
void detail::ValidateVisitor::Nested(std::string_view key, const S& sub, bool /*optional*/) {
  if constexpr (kIsOptional<S>) {
    if (sub) pr_.Append(Validate(*sub, JoinKey(prefix_, key)));
  } else {
    pr_.Append(Validate(sub, JoinKey(prefix_, key)));
  }
}

template <class E>
void detail::ValidateVisitor::List(const std::vector<E>& list, const Meta& m) {
  const std::string path = Path(m);
  if (static_cast<int>(list.size()) < m.min_size)
    pr_.Add(path, "needs at least " + std::to_string(m.min_size) + " entr" +
                      (m.min_size == 1 ? "y" : "ies") + ", has " + std::to_string(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i)
    pr_.Append(ValidateEntry(list[i], ListItemPath(path, i)));
}

/// A map: its number of keys (>= min_size), each key once and following `rule`, each value (a
/// struct by its own rules; a field by `m` without the key rule: bounds, choices, min_size).
template <class V>
void detail::ValidateVisitor::Map(const OrderedMap<V>& map, const Meta& m) {
  const std::string path = Path(m);
  if (static_cast<int>(map.size()) < m.min_size)
    pr_.Add(path, "needs at least " + Plural(static_cast<std::size_t>(m.min_size), "key", "keys") +
                      ", has " + std::to_string(map.size()));
  for (std::size_t i = 0; i < map.size(); ++i) {
    const auto& [key, value] = map[i];
    const std::string at = JoinKey(path, key);
    for (std::size_t j = 0; j < i; ++j)
      if (map[j].first == key) {
        pr_.Add(at, "given twice; give each key once");
        break;
      }
    CheckText(at, key, m, pr_);
    if constexpr (kIsStruct<V>) {
      pr_.Append(Validate(value, at));
    } else {
      Meta vm = m;
      vm.key = key;
      vm.rule = {};
      ValidateVisitor inner(pr_, path);
      inner.Field(value, vm);
    }
  }
}

/// Throws ConfigError listing every problem (file name used only for the message).
template <class P>
void ValidateOrThrow(const P& p, const std::string& file = "") {
  Problems pr = Validate(p);
  if (!pr.empty()) throw ConfigError(file, pr.items());
}

}  // namespace params
}  // namespace scw
