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

/// One row per field: key, type, unit, default, bounds, tuning scale (with the resolution of tuned
/// values, "log, step 0.01"), required, description.
template <class P>
std::string MarkdownTable(const P& defaults = P{}) {
  std::string out =
      "| Key | Type | Unit | Default | Bounds | Tuning | Required | Description |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  ForEachField(defaults, [&](const std::string& path, const auto& value, const Meta& m) {
    using T = std::decay_t<decltype(value)>;
    const char* type = std::is_same_v<T, double>                ? "double"
                       : std::is_same_v<T, int>                 ? "int"
                       : std::is_same_v<T, bool>                ? "bool"
                       : std::is_same_v<T, std::vector<double>> ? "double[]"
                                                                : "string";
    std::string bounds = "";
    if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int> ||
                  std::is_same_v<T, std::vector<double>>)
      bounds = detail::BoundsText(m.lo, m.hi);
    out += "| `" + path + "` | " + type + " | " + detail::EscapeCell(m.unit) + " | `" +
           detail::EscapeCell(detail::RenderValue(value)) + "` | " + bounds + " | " +
           detail::ScaleName(m.scale) +
           (m.scale != Scale::kFixed && m.resolution > 0 ? ", step " + FormatNumber(m.resolution)
                                                         : std::string()) +
           " | " + (m.optional ? (m.workspace_only ? "no (workspace only)" : "no") : "yes") +
           " | " + detail::EscapeCell(m.doc) + " |\n";
  });
  return out;
}

}  // namespace scw::params
