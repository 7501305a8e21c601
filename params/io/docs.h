// Markdown reference tables generated from the schema (the single description of each field).
#pragma once

#include <string>
#include <type_traits>

#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::params {

namespace detail {
std::string BoundsText(double lo, double hi);
std::string EscapeCell(std::string_view s);
const char* ScaleName(Scale s);
}  // namespace detail

namespace detail {

/// The rows of MarkdownTable for the fields of `p`, keys prefixed with `prefix`.
template <class P>
void MarkdownRows(const P& p, const std::string& prefix, std::string* out) {
  ForEachField(
      p,
      [&](const std::string& path, const auto& value, const Meta& m) {
        using T = std::decay_t<decltype(value)>;
        const char* type = kIsList<T>                               ? "list"
                           : std::is_same_v<T, double>              ? "double"
                           : std::is_same_v<T, int>                 ? "int"
                           : std::is_same_v<T, bool>                ? "bool"
                           : std::is_same_v<T, std::vector<double>> ? "double[]"
                                                                    : "string";
        std::string bounds = "", shown;
        if constexpr (kIsList<T>) {
          bounds = ">= " + std::to_string(m.min_size) + (m.min_size == 1 ? " entry" : " entries");
          shown = value.empty() ? "[]" : std::to_string(value.size()) + " entries";
        } else {
          if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int> ||
                        std::is_same_v<T, std::vector<double>>)
            bounds = BoundsText(m.lo, m.hi);
          shown = RenderValue(value);
        }
        *out +=
            "| `" + path + "` | " + type + " | " + EscapeCell(m.unit) + " | `" + EscapeCell(shown) +
            "` | " + bounds + " | " + ScaleName(m.scale) +
            (m.scale != Scale::kFixed && m.resolution > 0 ? ", step " + FormatNumber(m.resolution)
                                                          : std::string()) +
            " | " + (m.optional ? (m.workspace_only ? "no (workspace only)" : "no") : "yes") +
            " | " + EscapeCell(m.doc) + " |\n";
        // A list's entry fields follow it as `key[].field`, with the entry's defaults.
        if constexpr (kIsList<T>) MarkdownRows(typename T::value_type{}, path + "[]", out);
      },
      prefix);
}

}  // namespace detail

/// One row per field: key, type, unit, default, bounds, tuning scale (with the resolution of tuned
/// values, "log, step 0.01"), required, description. A list (`v.List`) is one row, followed by
/// one row per field of its entries (`parameters[].lo`).
template <class P>
std::string MarkdownTable(const P& defaults = P{}) {
  std::string out =
      "| Key | Type | Unit | Default | Bounds | Tuning | Required | Description |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  detail::MarkdownRows(defaults, "", &out);
  return out;
}

}  // namespace scw::params
