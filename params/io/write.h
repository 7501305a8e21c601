// YAML writing of schema structs, by hand rather than through yaml-cpp's emitter, so that every
// literal has the type the car's node declares (ecosystem spec §3.2–3.3):
//   doubles: shortest round-trip text (std::to_chars), always with '.' or an exponent (8.0, 4e-05)
//   integers: plain decimal; booleans: true/false; strings: double-quoted
//   arrays: flow style [a, b], non-empty; nested maps in schema order; each key once; no anchors.
// Lists of structs (`v.List`, plain workspace files only) are block sequences of one-line flow
// maps, `  - {key: a, lo: 1.0}`, whose text values are plain where they read back unchanged; a
// block alternative of a variant entry is `  - {monte_carlo: {name: a, ...}}`. Maps (`v.Map`) and
// text lists are flow collections, `{gg_scale: [1.0, 1.1]}`, `[kind=clean, laps=2]`; a
// std::optional member is written only when present.
// This renders text only; files are written with io::WriteFileAtomic (params/io/atomic_file.h).
#pragma once

#include <functional>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

/// Shortest round-trip text of a double that YAML/rcl reads back as a double.
std::string FormatDouble(double x);
std::string FormatDoubleList(const std::vector<double>& v);
std::string QuoteString(const std::string& s);
/// A text value inside a flow map: plain when it reads back as the same text (letters, digits,
/// _ . - + = /, starting with a letter, digit or _, not a null word), else double-quoted
/// (`ESC.x[1]` → "ESC.x[1]").
std::string FlowScalar(const std::string& s);

struct EmitEntry {
  std::string key;                      ///< dotted path
  std::string value;                    ///< rendered literal
  std::string comment;                  ///< optional trailing comment (unit)
  bool list = false;                    ///< a list of structs: `items` are its entries (flow maps)
  std::vector<std::string> items = {};  ///< list entries, each rendered as one flow map
};

/// Renders entries (dotted keys) as nested YAML. With a non-empty node_key the result is wrapped
/// in `<node_key>: ros__parameters:`. `header` lines are emitted as comments at the top.
std::string EmitNested(const std::vector<EmitEntry>& entries, const std::string& node_key,
                       const std::string& header);

/// How text values outside flow maps are written (inside flow maps and flow lists they are
/// always FlowScalar).
enum class TextStyle {
  kQuoted,          ///< double-quoted (vehicle, scenario, space files)
  kPlainWhereSafe,  ///< FlowScalar: plain where it reads back unchanged (scenario sets)
};

namespace detail {
template <class E>
std::string RenderFlowMap(const E& e);

/// The text of one value. `flow`: inside a flow map or list (texts as FlowScalar). An absent
/// std::optional renders as "" (the writers leave it out).
template <class T>
std::string RenderValue(const T& v, bool flow = false) {
  if constexpr (kIsOptional<T>) {
    return v ? RenderValue(*v, flow) : std::string();
  } else if constexpr (kIsList<T>) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + RenderFlowMap(v[i]);
    return out + "]";
  } else if constexpr (kIsMap<T>) {
    std::string out;
    for (const auto& [key, value] : v)
      out += (out.empty() ? "{" : ", ") + FlowScalar(key) + ": " + RenderValue(value, true);
    return out.empty() ? "{}" : out + "}";
  } else if constexpr (kIsStruct<T> || kIsVariant<T>) {
    return RenderFlowMap(v);
  } else if constexpr (std::is_same_v<T, double>) {
    return FormatDouble(v);
  } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::int64_t>) {
    return std::to_string(v);
  } else if constexpr (std::is_same_v<T, bool>) {
    return v ? "true" : "false";
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    return FormatDoubleList(v);
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + FlowScalar(v[i]);
    return out + "]";
  } else {
    static_assert(std::is_same_v<T, std::string>);
    return flow ? FlowScalar(v) : QuoteString(v);
  }
}

/// The top-level fields of one struct as flow-map items (nested structs, lists and maps rendered
/// inline).
class FlowItems {
 public:
  struct Item {
    std::string_view key;
    std::string text;
    bool omit_default;
    bool absent = false;  ///< an absent std::optional: left out
  };
  template <class T>
  void Field(const T& v, const Meta& m) {
    Add(m.key, v, m.omit_default);
  }
  template <class E>
  void List(const E& v, const Meta& m) {
    Add(m.key, v, m.omit_default);
  }
  template <class M>
  void Map(const M& v, const Meta& m) {
    Add(m.key, v, m.omit_default);
  }
  template <class S>
  void Nested(std::string_view key, const S& sub, bool /*optional*/ = false) {
    Add(key, sub, false);
  }
  std::vector<Item> items;

 private:
  template <class T>
  void Add(std::string_view key, const T& v, bool omit_default) {
    bool absent = false;
    if constexpr (kIsOptional<T>) absent = !v.has_value();
    items.push_back({key, RenderValue(v, true), omit_default, absent});
  }
};

/// `{key: value, ...}` in schema order; a field marked omit_default is left out while its text
/// equals that of the in-class default, an absent std::optional always. A variant list entry is
/// its alternative's map, a block (kBlock) wrapped as `{block-key: {...}}`.
template <class E>
std::string RenderFlowMap(const E& e) {
  if constexpr (kIsVariant<E>) {
    return std::visit(
        [](const auto& alt) {
          using A = std::decay_t<decltype(alt)>;
          if constexpr (requires { A::kBlock; })
            return "{" + std::string(A::kBlock.key) + ": " + RenderFlowMap(alt) + "}";
          else
            return RenderFlowMap(alt);
        },
        e);
  } else {
    FlowItems mine, defaults;
    E::Visit(e, mine);
    const E def{};
    E::Visit(def, defaults);
    std::string out;
    for (std::size_t i = 0; i < mine.items.size(); ++i) {
      const auto& it = mine.items[i];
      if (it.absent || (it.omit_default && it.text == defaults.items[i].text)) continue;
      out += (out.empty() ? "{" : ", ") + std::string(it.key) + ": " + it.text;
    }
    return out.empty() ? "{}" : out + "}";
  }
}
}  // namespace detail

template <class P>
std::set<std::string> DifferingKeys(const P& a, const P& b);

/// The fields of `p` selected by `include(path, meta)`, rendered (keys prefixed with `prefix`).
/// A present std::optional group contributes its own fields (all of them, it is complete; only
/// the omit_default ones that hold their default are left out, as at the top level).
template <class P>
std::vector<EmitEntry> CollectEntries(
    const P& p, const std::function<bool(const std::string&, const Meta&)>& include,
    TextStyle text = TextStyle::kQuoted, const std::string& prefix = "") {
  std::vector<EmitEntry> out;
  ForEachField(
      p,
      [&](const std::string& path, const auto& value, const Meta& meta) {
        using T = std::decay_t<decltype(value)>;
        using U = UnoptionalT<T>;
        if (!include(path, meta)) return;
        if constexpr (kIsOptional<T>) {
          if (!value) return;
        }
        const U& v = [&]() -> const U& {
          if constexpr (kIsOptional<T>)
            return *value;
          else
            return value;
        }();
        if constexpr (kIsStruct<U>) {
          // Complete, except the omit_default fields that hold their default.
          const std::set<std::string> changed = DifferingKeys(v, U{});
          const std::size_t cut = path.size() + 1;
          auto inner = CollectEntries(
              v,
              [&](const std::string& sub, const Meta& m) {
                return !m.omit_default || changed.count(sub.substr(cut)) > 0;
              },
              text, path);
          out.insert(out.end(), inner.begin(), inner.end());
        } else if constexpr (kIsList<U>) {
          EmitEntry e{path, "", "", true, {}};
          for (const auto& item : v) e.items.push_back(detail::RenderFlowMap(item));
          out.push_back(std::move(e));
        } else {
          out.push_back({path, detail::RenderValue(v, text == TextStyle::kPlainWhereSafe), ""});
        }
      },
      prefix);
  return out;
}

/// Dotted keys whose values differ between `a` and `b` (same type P).
template <class P>
std::set<std::string> DifferingKeys(const P& a, const P& b) {
  std::vector<std::pair<std::string, std::string>> va, vb;
  ForEachField(a, [&](const std::string& path, const auto& v, const Meta&) {
    va.emplace_back(path, detail::RenderValue(v));
  });
  ForEachField(b, [&](const std::string& path, const auto& v, const Meta&) {
    vb.emplace_back(path, detail::RenderValue(v));
  });
  std::set<std::string> out;
  for (std::size_t i = 0; i < va.size(); ++i)
    if (va[i].second != vb[i].second) out.insert(va[i].first);
  return out;
}

/// Full ROS 2 params file of `p` for node `node_key`: every required key, plus each optional key
/// that `present` names (keys the source file set) or whose value differs from the default.
template <class P>
std::string ToRosYaml(const P& p, const std::string& node_key,
                      const std::set<std::string>& present = {}, const std::string& header = "") {
  const std::set<std::string> changed = DifferingKeys(p, P{});
  auto entries = CollectEntries(p, [&](const std::string& path, const Meta& meta) {
    return !meta.optional || present.count(path) || changed.count(path);
  });
  return EmitNested(entries, node_key, header);
}

/// Overrides-only ROS 2 params file: just the keys whose values differ from `base`, to be loaded
/// after the base file (later params files override earlier ones).
template <class P>
std::string ToRosOverrides(const P& p, const P& base, const std::string& node_key,
                           const std::string& header = "") {
  const std::set<std::string> changed = DifferingKeys(p, base);
  auto entries = CollectEntries(
      p, [&](const std::string& path, const Meta&) { return changed.count(path) > 0; });
  return EmitNested(entries, node_key, header);
}

/// Plain nested YAML of every field (workspace files: vehicle, scenario, space …), except the
/// omit_default fields that hold their default and the absent std::optional ones.
template <class P>
std::string ToPlainYaml(const P& p, const std::string& header = "",
                        TextStyle text = TextStyle::kQuoted) {
  const std::set<std::string> changed = DifferingKeys(p, P{});
  auto entries = CollectEntries(
      p,
      [&](const std::string& path, const Meta& meta) {
        return !meta.omit_default || changed.count(path) > 0;
      },
      text);
  return EmitNested(entries, "", header);
}

}  // namespace scw::params
