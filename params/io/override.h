// Command-line overrides `--set key=value` for any schema struct: the dotted key names a field,
// the value is read with the same typing rules as the YAML files (a list as [a, b]). Every
// override is checked; problems are collected and thrown together, naming the override.
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include "params/io/load.h"
#include "params/io/yaml_doc.h"
#include "params/schema/field.h"

namespace scw::params {

/// Applies "key=value" overrides to `p` in order, then validates the result. Throws ConfigError
/// (source "--set") listing every problem.
template <class P>
void ApplyOverrides(P& p, const std::vector<std::string>& overrides) {
  Problems problems;
  std::vector<std::string> known;
  ForEachField(p, [&](const std::string& path, auto&, const Meta&) { known.push_back(path); });
  for (const auto& item : overrides) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      problems.Add(item, "an override must look like key=value");
      continue;
    }
    const std::string key = item.substr(0, eq);
    const std::string text = item.substr(eq + 1);
    bool found = false;
    ForEachField(p, [&](const std::string& path, auto& value, const Meta& meta) {
      if (path != key) return;
      found = true;
      YamlNode node;
      try {
        node = ParseYaml(text.empty() ? std::string("''") : text, "--set " + key);
      } catch (const ConfigError&) {
        problems.Add(key, "cannot read the value '" + text + "'");
        return;
      }
      using T = std::decay_t<decltype(value)>;
      std::string err, note;
      if constexpr (std::is_same_v<T, std::string>) {
        value = text;  // strings verbatim (paths may contain YAML-special characters)
      } else if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::vector<double>>) {
        err = detail::ConvertLeaf(node, meta, /*accept_int=*/true, &value, &note);
      } else {
        err = detail::ConvertLeaf(node, meta, &value);
      }
      if (!err.empty()) problems.Add(key, err);
    });
    if (!found) {
      std::string msg = "unknown key";
      const std::string hint = detail::SuggestKey(key, known);
      if (!hint.empty()) msg += " (did you mean " + hint + "?)";
      problems.Add(key, msg);
    }
  }
  if (problems.empty()) problems = Validate(p);
  if (!problems.empty()) throw ConfigError("--set", problems.items());
}

}  // namespace scw::params
