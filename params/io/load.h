// Strict loading of any schema struct (params/schema/field.h) from YAML.
//
// Every problem of a file is collected and reported at once in one ConfigError, each as
// `file: dotted.key: rule (line N)`: unknown keys, keys given twice, missing required keys, wrong
// types (an integer literal where the car's node declares a double is an error: the node would
// reject the file at start-up), NaN/inf, out-of-bounds values, empty or non-homogeneous arrays and
// the struct's cross-field rules (equal array lengths, threshold orderings).
//
// Import mode (`lenient`) accepts what the car's node itself accepts — duplicates (the last value
// wins, as in the ROS 2 parser), unknown keys (ignored by the node), integer literals for doubles
// (normalised) — and reports each of them as a note; bounds and rules still apply.
#pragma once

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "params/io/yaml_doc.h"
#include "params/schema/field.h"

namespace scw::params {

struct LoadOptions {
  Layout layout = Layout::kPlain;
  std::string node_key;         ///< kRos2: the fully qualified node name expected
  bool lenient = false;         ///< import mode (see above)
  bool int_for_double = false;  ///< accept `5` for a double silently (plain workspace files)
};

struct LoadReport {
  std::vector<Problem> notes;        ///< import-mode findings (duplicates, unknown keys, coercions)
  std::set<std::string> present;     ///< dotted keys the file sets
  std::map<std::string, int> lines;  ///< dotted key → source line of the value used
};

namespace detail {

/// Converts one YAML leaf into a field value; returns an empty string on success or the rule
/// that was broken. `note` receives a normalisation remark in lenient mode.
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool accept_int_for_double,
                        double* out, std::string* note);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, int* out);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, std::int64_t* out);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool* out);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool accept_int_for_double,
                        std::vector<double>* out, std::string* note);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, std::string* out);
/// A list of texts: each element a scalar, taken verbatim (its rule is checked by Validate).
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, std::vector<std::string>* out);

/// The node at the dotted `path` below `map` (through nested maps or dotted keys; the last one
/// when given twice), or nullptr.
const YamlNode* FindNode(const YamlNode* map, const std::string& path);

/// Closest schema key to an unknown key (same parent preferred), or empty.
std::string SuggestKey(const std::string& unknown, const std::vector<std::string>& known);
/// Unknown keys of one file that get a "did you mean" hint: past this many the file is most
/// likely not of this kind at all (or its indentation is broken), and hints would be noise.
inline constexpr int kMaxKeySuggestions = 16;
/// A small map of a plain file (a list entry, a Monte-Carlo block) names its keys after an
/// unknown key that resembles none of them.
inline constexpr std::size_t kMaxKeysListed = 8;

std::string LineSuffix(int line);
/// "the double 2.5", "a list [1, 2]", "a map", "an empty value": what a node is, for messages.
std::string Got(const YamlNode& node);

}  // namespace detail

namespace detail {

/// What one load shares across the maps it reads (the file's root map and every list entry).
struct LoadContext {
  const LoadOptions& opt;
  Problems& problems;
  LoadReport& rep;
  int suggestions = 0;
};

/// "key, lo, hi": the keys of a list entry, for messages.
template <class E>
std::string KeyList() {
  std::string out;
  E e{};
  ForEachField(e, [&](const std::string& path, const auto&, const Meta&) {
    out += (out.empty() ? "" : ", ") + path;
  });
  return out;
}

/// What a list entry looks like, for messages: "{key, lo, hi}", or for a variant entry
/// "{name, weight} or {monte_carlo: {...}}".
template <class A>
std::string AlternativeShape() {
  if constexpr (requires { A::kBlock; })
    return "{" + std::string(A::kBlock.key) + ": {...}}";
  else
    return "{" + KeyList<A>() + "}";
}
template <class E, std::size_t... I>
std::string AlternativesShape(std::index_sequence<I...>) {
  std::string out;
  ((out += (I ? " or " : "") + AlternativeShape<std::variant_alternative_t<I, E>>()), ...);
  return out;
}
template <class E>
std::string EntryShape() {
  if constexpr (kIsVariant<E>)
    return AlternativesShape<E>(std::make_index_sequence<std::variant_size_v<E>>{});
  else
    return AlternativeShape<E>();
}

template <class P>
void LoadMap(P& p, const FlatDoc& doc, const std::string& prefix, int map_line, LoadContext& ctx);

/// One field value from its node; returns the broken rule or "" (`note`: lenient-mode remark).
template <class T>
std::string ConvertField(T& value, const YamlNode& node, const Meta& meta, const LoadContext& ctx,
                         std::string* note) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::vector<double>>)
    return ConvertLeaf(node, meta, ctx.opt.int_for_double || ctx.opt.lenient, &value, note);
  else
    return ConvertLeaf(node, meta, &value);
}

/// The lines of a text list's elements (their rules are reported per element: "set[2]").
inline void RecordItemLines(const YamlNode& node, const std::string& path, LoadReport& rep) {
  if (node.kind != YamlNode::Kind::kSequence) return;
  for (std::size_t i = 0; i < node.items.size(); ++i)
    rep.lines[ListItemPath(path, i)] = node.items[i].line;
}

/// A struct written as the map `node` (a list entry, a block, a map value).
template <class S>
void LoadStruct(S& out, const YamlNode& node, const std::string& path, LoadContext& ctx) {
  if (node.kind != YamlNode::Kind::kMap) {
    ctx.problems.Add(
        path, "expected a map {" + KeyList<S>() + "}, got " + Got(node) + LineSuffix(node.line));
    return;
  }
  Problems located;  // cannot happen for a map: Flatten only reports on the root's kind
  const FlatDoc doc = Flatten(node, Layout::kPlain, "", &located);
  LoadMap(out, doc, path, node.line, ctx);
}

/// Alternative A of a variant entry, when A is a block (kBlock) whose key the entry map holds:
/// the entry is then `{key: {...}}` and nothing else.
template <class A, class E>
bool LoadBlock(E& out, const YamlNode& item, const std::string& at, LoadContext& ctx) {
  if constexpr (!requires { A::kBlock; }) {
    return false;
  } else {
    const std::string key(A::kBlock.key);
    const YamlNode* value = nullptr;
    std::string lines;
    int given = 0;
    for (const auto& [k, v] : item.entries)
      if (k == key) {
        value = &v;
        lines += (given++ ? ", " : "") + std::to_string(v.line);
      }
    if (!value) return false;
    const std::string path = JoinKey(at, key);
    if (given > 1)
      ctx.problems.Add(path, "given " + std::to_string(given) + " times (lines " + lines +
                                 "); give each key once");
    for (const auto& [k, v] : item.entries)
      if (k != key)
        ctx.problems.Add(JoinKey(at, k),
                         "unknown key: a " + key + " entry has no other keys" + LineSuffix(v.line));
    ctx.rep.lines[path] = value->line;
    ctx.rep.present.insert(path);
    LoadStruct(out.template emplace<A>(), *value, path, ctx);
    return true;
  }
}
template <class E, std::size_t... I>
bool LoadAnyBlock(E& out, const YamlNode& item, const std::string& at, LoadContext& ctx,
                  std::index_sequence<I...>) {
  return (LoadBlock<std::variant_alternative_t<I, E>>(out, item, at, ctx) || ...);
}

/// One list entry (a map): a struct, or a variant's block or else its first alternative.
template <class E>
void LoadEntry(E& out, const YamlNode& item, const std::string& at, LoadContext& ctx) {
  if constexpr (kIsVariant<E>) {
    if (LoadAnyBlock(out, item, at, ctx, std::make_index_sequence<std::variant_size_v<E>>{}))
      return;
    LoadStruct(out.template emplace<0>(), item, at, ctx);
  } else {
    LoadStruct(out, item, at, ctx);
  }
}

/// A `v.List` field: a YAML sequence whose items are maps, each loaded as one E.
template <class E>
void LoadList(std::vector<E>& out, const YamlNode& node, const std::string& path,
              LoadContext& ctx) {
  if (node.kind != YamlNode::Kind::kSequence) {
    ctx.problems.Add(path, "expected a list of maps " + EntryShape<E>() + ", got " + Got(node) +
                               LineSuffix(node.line));
    return;
  }
  out.assign(node.items.size(), E{});
  for (std::size_t i = 0; i < node.items.size(); ++i) {
    const YamlNode& item = node.items[i];
    const std::string at = ListItemPath(path, i);
    ctx.rep.lines[at] = item.line;
    if (item.kind != YamlNode::Kind::kMap) {
      ctx.problems.Add(
          at, "expected a map " + EntryShape<E>() + ", got " + Got(item) + LineSuffix(item.line));
      continue;
    }
    LoadEntry(out[i], item, at, ctx);
  }
}

/// A `v.Map` field: the entries of the map `node` in file order, each key once; a struct value
/// is a map of its own, any other value a field under `meta`.
template <class V>
void LoadMapField(OrderedMap<V>& out, const YamlNode& node, const std::string& path,
                  const Meta& meta, LoadContext& ctx) {
  out.clear();
  for (std::size_t i = 0; i < node.entries.size(); ++i) {
    const auto& [key, value] = node.entries[i];
    const std::string at = JoinKey(path, key);
    bool again = false;
    for (std::size_t j = 0; j < i && !again; ++j) again = node.entries[j].first == key;
    if (again) {
      ctx.problems.Add(at, "given twice (line " + std::to_string(value.line) +
                               " repeats a key given above); give each key once");
      continue;
    }
    ctx.rep.lines[at] = value.line;
    ctx.rep.present.insert(at);
    out.emplace_back(key, V{});
    V& target = out.back().second;
    if constexpr (kIsStruct<V>) {
      LoadStruct(target, value, at, ctx);
    } else {
      std::string note;
      const std::string err = ConvertField(target, value, meta, ctx, &note);
      if (!err.empty()) ctx.problems.Add(at, err + LineSuffix(value.line));
      if constexpr (std::is_same_v<V, std::vector<std::string>>)
        RecordItemLines(value, at, ctx.rep);
    }
  }
}

/// Loads the fields of `p` from the entries of one map (dotted keys relative to it); problems and
/// report keys carry `prefix`. `map_line` (> 0 for list entries) is named for missing keys.
template <class P>
void LoadMap(P& p, const FlatDoc& doc, const std::string& prefix, int map_line, LoadContext& ctx) {
  const LoadOptions& opt = ctx.opt;
  Problems& problems = ctx.problems;
  LoadReport& rep = ctx.rep;
  auto full = [&](const std::string& key) { return JoinKey(prefix, key); };

  std::map<std::string, std::vector<const YamlNode*>> by_key;
  for (const auto& e : doc.entries) by_key[e.key].push_back(e.node);

  // Maps (v.Map) and std::optional groups read the keys below them themselves.
  std::vector<std::string> own;
  ForEachField(p, [&](const std::string& path, const auto& value, const Meta&) {
    using U = UnoptionalT<std::decay_t<decltype(value)>>;
    if constexpr (kIsMap<U> || kIsStruct<U>) own.push_back(path);
  });
  auto below = [](const std::string& key, const std::string& base) {
    return key.size() > base.size() && key.compare(0, base.size(), base) == 0 &&
           key[base.size()] == '.';
  };
  auto owned = [&](const std::string& key) {
    return std::any_of(own.begin(), own.end(), [&](const std::string& o) { return below(key, o); });
  };

  for (const auto& [key, nodes] : by_key) {
    if (nodes.size() < 2 || owned(key)) continue;
    std::string msg = "given " + std::to_string(nodes.size()) + " times (";
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (i) msg += ", ";
      msg += "line " + std::to_string(nodes[i]->line) + ": " + Render(*nodes[i]);
    }
    msg += "); the car's node uses the last one (" + Render(*nodes.back()) + ")";
    if (opt.lenient)
      rep.notes.push_back({full(key), msg + ", imported as that"});
    else
      problems.Add(full(key), msg + "; give each key once");
  }

  std::set<std::string> consumed;
  std::vector<std::string> known;
  ForEachField(p, [&](const std::string& path, auto& value, const Meta& meta) {
    using T = std::decay_t<decltype(value)>;
    using U = UnoptionalT<T>;
    known.push_back(path);
    // The member itself, or the value of a present std::optional member.
    auto target = [&]() -> U& {
      if constexpr (kIsOptional<T>)
        return value.emplace();
      else
        return value;
    };
    const bool required = !meta.optional && !kIsOptional<T>;
    auto it = by_key.find(path);

    if constexpr (kIsMap<U> || kIsStruct<U>) {
      std::vector<FlatEntry> sub;  // keys relative to the map or group
      for (const auto& e : doc.entries)
        if (below(e.key, path)) {
          sub.push_back({e.key.substr(path.size() + 1), e.node});
          consumed.insert(e.key);
        }
      if (it != by_key.end()) {  // a value where the map belongs
        consumed.insert(path);
        const YamlNode& node = *it->second.back();
        problems.Add(full(path), "expected a map, got " + Got(node) + LineSuffix(node.line));
        return;
      }
      const YamlNode* node = FindNode(doc.map, path);
      if (!node && sub.empty()) {
        if (required) problems.Add(full(path), "required key is missing" + LineSuffix(map_line));
        return;
      }
      const int line = node ? node->line : sub.front().node->line;
      rep.present.insert(full(path));
      rep.lines[full(path)] = line;
      if constexpr (kIsStruct<U>) {
        FlatDoc group;
        group.entries = std::move(sub);
        group.map = node;
        LoadMap(target(), group, full(path), line, ctx);
      } else if (node) {
        LoadMapField(target(), *node, full(path), meta, ctx);
      } else {  // `key.sub: value` cannot tell where a map key with dots ends
        problems.Add(full(path), "write it as a map (" + path +
                                     ": {key: value}), not as dotted "
                                     "keys" +
                                     LineSuffix(line));
      }
      return;
    } else {
      if (it == by_key.end()) {
        // A map where a value was expected shows up as deeper keys.
        const std::string deeper = path + ".";
        auto sub = by_key.lower_bound(deeper);
        if (sub != by_key.end() && sub->first.compare(0, deeper.size(), deeper) == 0) {
          problems.Add(full(path), std::string(kIsList<U>     ? "expected a list of maps"
                                               : kIsVector<U> ? "expected a list"
                                                              : "expected a value") +
                                       ", got a map" + LineSuffix(sub->second.front()->line));
          for (auto s = sub; s != by_key.end() && s->first.compare(0, deeper.size(), deeper) == 0;
               ++s)
            consumed.insert(s->first);
        } else if (required) {
          problems.Add(full(path), "required key is missing" + LineSuffix(map_line));
        }
        return;
      }
      consumed.insert(path);
      const YamlNode& node = *it->second.back();
      rep.present.insert(full(path));
      rep.lines[full(path)] = node.line;
      std::string err, note;
      if constexpr (kIsList<U>) {
        LoadList(target(), node, full(path), ctx);
      } else {
        err = ConvertField(target(), node, meta, ctx, &note);
        if constexpr (std::is_same_v<U, std::vector<std::string>>)
          RecordItemLines(node, full(path), rep);
      }
      if (!err.empty()) problems.Add(full(path), err + LineSuffix(node.line));
      if (!note.empty() && opt.lenient && !opt.int_for_double)
        rep.notes.push_back({full(path), note + LineSuffix(node.line)});
    }
  });

  for (const auto& [key, nodes] : by_key) {
    if (consumed.count(key)) continue;
    std::string msg = opt.layout == Layout::kRos2
                          ? "unknown key: the car's node would silently ignore it and keep its "
                            "code default"
                          : "unknown key";
    const std::string hint = ctx.suggestions++ < kMaxKeySuggestions ? SuggestKey(key, known) : "";
    if (!hint.empty()) {
      msg += " (did you mean " + hint + "?)";
    } else if (opt.layout == Layout::kPlain && known.size() <= kMaxKeysListed) {
      std::string all;
      for (const auto& k : known) all += (all.empty() ? "" : ", ") + k;
      msg += " (expected " + all + ")";
    }
    msg += LineSuffix(nodes.front()->line);
    if (opt.lenient)
      rep.notes.push_back({full(key), msg + "; dropped"});
    else
      problems.Add(full(key), msg);
  }
}

}  // namespace detail

/// Loads `P` from YAML text. Throws ConfigError listing every problem.
template <class P>
P LoadFromText(const std::string& text, const std::string& file, const LoadOptions& opt,
               LoadReport* report = nullptr) {
  LoadReport local;
  LoadReport& rep = report ? *report : local;
  Problems problems;
  const YamlNode root = ParseYaml(text, file);
  const FlatDoc doc = Flatten(root, opt.layout, opt.node_key, &problems);
  // No parameter map at all (an empty file, a list, no node section): that one problem, not
  // also every required key as missing.
  if (doc.map == nullptr && !problems.empty()) throw ConfigError(file, problems.items());

  P p{};
  detail::LoadContext ctx{opt, problems, rep};
  detail::LoadMap(p, doc, "", 0, ctx);

  if (problems.empty()) {
    // Type-level parsing succeeded: now bounds, array rules and cross-field rules.
    const Problems rules = Validate(p);
    for (const auto& pr : rules.items()) {
      auto line = rep.lines.find(pr.path);
      problems.Add(pr.path, pr.message + (line != rep.lines.end() ? detail::LineSuffix(line->second)
                                                                  : std::string()));
    }
  }
  if (!problems.empty()) throw ConfigError(file, problems.items());
  return p;
}

template <class P>
P LoadFromFile(const std::string& path, const LoadOptions& opt, LoadReport* report = nullptr) {
  return LoadFromText<P>(ReadTextFile(path), path, opt, report);
}

/// Plain workspace files (vehicle, scenario, space …): integer literals are accepted for doubles.
template <class P>
P LoadPlainText(const std::string& text, const std::string& name) {
  LoadOptions opt;
  opt.layout = Layout::kPlain;
  opt.int_for_double = true;
  return LoadFromText<P>(text, name, opt);
}
template <class P>
P LoadPlainFile(const std::string& path) {
  return LoadPlainText<P>(ReadTextFile(path), path);
}

/// The car's ROS 2 params file of node `node_key`, strictly.
template <class P>
P LoadRosFile(const std::string& path, const std::string& node_key, LoadReport* report = nullptr) {
  LoadOptions opt;
  opt.layout = Layout::kRos2;
  opt.node_key = node_key;
  return LoadFromFile<P>(path, opt, report);
}
template <class P>
P LoadRosText(const std::string& text, const std::string& name, const std::string& node_key,
              LoadReport* report = nullptr) {
  LoadOptions opt;
  opt.layout = Layout::kRos2;
  opt.node_key = node_key;
  return LoadFromText<P>(text, name, opt, report);
}

}  // namespace scw::params
