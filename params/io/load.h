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
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool* out);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool accept_int_for_double,
                        std::vector<double>* out, std::string* note);
std::string ConvertLeaf(const YamlNode& node, const Meta& meta, std::string* out);

/// Closest schema key to an unknown key (same parent preferred), or empty.
std::string SuggestKey(const std::string& unknown, const std::vector<std::string>& known);
/// Unknown keys of one file that get a "did you mean" hint: past this many the file is most
/// likely not of this kind at all (or its indentation is broken), and hints would be noise.
inline constexpr int kMaxKeySuggestions = 16;

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

template <class P>
void LoadMap(P& p, const std::vector<FlatEntry>& entries, const std::string& prefix, int map_line,
             LoadContext& ctx);

/// A `v.List` field: a YAML sequence whose items are maps, each loaded as one E.
template <class E>
void LoadList(std::vector<E>& out, const YamlNode& node, const std::string& path,
              LoadContext& ctx) {
  if (node.kind != YamlNode::Kind::kSequence) {
    ctx.problems.Add(path, "expected a list of maps {" + KeyList<E>() + "}, got " + Got(node) +
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
          at, "expected a map {" + KeyList<E>() + "}, got " + Got(item) + LineSuffix(item.line));
      continue;
    }
    Problems located;  // cannot happen for a map: Flatten only reports on the root's kind
    const FlatDoc doc = Flatten(item, Layout::kPlain, "", &located);
    LoadMap(out[i], doc.entries, at, item.line, ctx);
  }
}

/// Loads the fields of `p` from the entries of one map (dotted keys relative to it); problems and
/// report keys carry `prefix`. `map_line` (> 0 for list entries) is named for missing keys.
template <class P>
void LoadMap(P& p, const std::vector<FlatEntry>& entries, const std::string& prefix, int map_line,
             LoadContext& ctx) {
  const LoadOptions& opt = ctx.opt;
  Problems& problems = ctx.problems;
  LoadReport& rep = ctx.rep;
  auto full = [&](const std::string& key) { return JoinKey(prefix, key); };

  std::map<std::string, std::vector<const YamlNode*>> by_key;
  for (const auto& e : entries) by_key[e.key].push_back(e.node);

  for (const auto& [key, nodes] : by_key) {
    if (nodes.size() < 2) continue;
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
    known.push_back(path);
    auto it = by_key.find(path);
    if (it == by_key.end()) {
      // A map where a value was expected shows up as deeper keys.
      const std::string deeper = path + ".";
      auto sub = by_key.lower_bound(deeper);
      if (sub != by_key.end() && sub->first.compare(0, deeper.size(), deeper) == 0) {
        problems.Add(full(path),
                     std::string(kIsList<T> ? "expected a list of maps" : "expected a value") +
                         ", got a map" + LineSuffix(sub->second.front()->line));
        for (auto s = sub; s != by_key.end() && s->first.compare(0, deeper.size(), deeper) == 0;
             ++s)
          consumed.insert(s->first);
      } else if (!meta.optional) {
        problems.Add(full(path), "required key is missing" + LineSuffix(map_line));
      }
      return;
    }
    consumed.insert(path);
    const YamlNode& node = *it->second.back();
    rep.present.insert(full(path));
    rep.lines[full(path)] = node.line;
    std::string err, note;
    const bool int_ok = opt.int_for_double || opt.lenient;
    if constexpr (kIsList<T>) {
      LoadList(value, node, full(path), ctx);
    } else if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::vector<double>>) {
      err = ConvertLeaf(node, meta, int_ok, &value, &note);
    } else {
      err = ConvertLeaf(node, meta, &value);
    }
    if (!err.empty()) problems.Add(full(path), err + LineSuffix(node.line));
    if (!note.empty() && opt.lenient && !opt.int_for_double)
      rep.notes.push_back({full(path), note + LineSuffix(node.line)});
  });

  for (const auto& [key, nodes] : by_key) {
    if (consumed.count(key)) continue;
    std::string msg = opt.layout == Layout::kRos2
                          ? "unknown key: the car's node would silently ignore it and keep its "
                            "code default"
                          : "unknown key";
    const std::string hint = ctx.suggestions++ < kMaxKeySuggestions ? SuggestKey(key, known) : "";
    if (!hint.empty()) msg += " (did you mean " + hint + "?)";
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

  P p{};
  detail::LoadContext ctx{opt, problems, rep};
  detail::LoadMap(p, doc.entries, "", 0, ctx);

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
