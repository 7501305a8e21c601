// Markdown reference tables generated from the schema (the single description of each field).
#pragma once

#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::params {

namespace detail {
std::string BoundsText(double lo, double hi);
std::string EscapeCell(std::string_view s);
const char* ScaleName(Scale s);

/// A table's rows and what is too long for a cell of them.
struct TableText {
  std::string rows;
  std::string notes;  ///< one list item per long description or default, in row order
};
/// Longest cell the table holds [bytes]: a longer description or default goes under the table in
/// full, and its cell keeps the lead (the docs' rule: no table cell over 300 characters).
inline constexpr std::size_t kMaxCell = 280;
/// The lead of a long cell: its first sentence when that fits, else its words up to the limit.
std::string Lead(const std::string& cell);
}  // namespace detail

namespace detail {

template <class T>
std::string TypeName() {
  if constexpr (kIsOptional<T>) {
    return TypeName<UnoptionalT<T>>();
  } else if constexpr (kIsList<T>) {
    return "list";
  } else if constexpr (kIsMap<T>) {
    using V = typename T::value_type::second_type;
    if constexpr (kIsStruct<V>)
      return "map";
    else
      return "map of " + TypeName<V>();
  } else if constexpr (kIsStruct<T>) {
    return "map";
  } else {
    return std::is_same_v<T, double>                     ? "double"
           : std::is_same_v<T, int>                      ? "int"
           : std::is_same_v<T, std::int64_t>             ? "int64"
           : std::is_same_v<T, bool>                     ? "bool"
           : std::is_same_v<T, std::vector<double>>      ? "double[]"
           : std::is_same_v<T, std::vector<std::string>> ? "string[]"
                                                         : "string";
  }
}

/// The Bounds cell: numeric bounds, sizes, and the text rule ("keys: a scenario key").
template <class T>
std::string BoundsCell(const Meta& m) {
  std::string out;
  auto add = [&](const std::string& part) {
    if (!part.empty()) out += (out.empty() ? "" : "; ") + part;
  };
  auto at_least = [&](const char* one, const char* many) {
    return ">= " + std::to_string(m.min_size) + " " + (m.min_size == 1 ? one : many);
  };
  if constexpr (kIsList<T>) {
    add(at_least("entry", "entries"));
  } else if constexpr (kIsMap<T>) {
    add(at_least("key", "keys"));
    if (!m.rule.doc.empty()) add("keys: " + std::string(m.rule.doc));
    using V = typename T::value_type::second_type;
    if constexpr (std::is_same_v<V, std::vector<std::string>>)
      add("each " + at_least("value", "values"));
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    add(at_least("value", "values"));
    if (!m.rule.doc.empty()) add("each: " + std::string(m.rule.doc));
  } else if constexpr (std::is_same_v<T, std::string>) {
    add(std::string(m.rule.doc));
  } else if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int> ||
                       std::is_same_v<T, std::int64_t> || std::is_same_v<T, std::vector<double>>) {
    add(BoundsText(m.lo, m.hi));
  }
  return out;
}

template <class T>
std::string DefaultCell(const T& value) {
  if constexpr (kIsOptional<T>) {
    return value ? DefaultCell(*value) : "—";
  } else if constexpr (kIsList<T>) {
    return "`" + (value.empty() ? std::string("[]") : std::to_string(value.size()) + " entries") +
           "`";
  } else {
    return "`" + EscapeCell(RenderValue(value)) + "`";
  }
}

inline void Row(const std::string& path, const std::string& type, std::string_view unit,
                const std::string& shown, const std::string& bounds, const Meta& m, bool required,
                std::string_view doc, TableText* out) {
  std::string shown_cell = shown;
  if (shown.size() > kMaxCell) {
    out->notes += "- `" + path + "`, default: " + shown + "\n";
    shown_cell = "(under the table)";
  }
  std::string doc_cell = EscapeCell(doc);
  if (doc_cell.size() > kMaxCell) {
    out->notes += "- `" + path + "`: " + doc_cell + "\n";
    doc_cell = Lead(doc_cell) + " (in full under the table)";
  }
  out->rows +=
      "| `" + path + "` | " + type + " | " + EscapeCell(unit) + " | " + shown_cell + " | " +
      EscapeCell(bounds) + " | " + ScaleName(m.scale) +
      (m.scale != Scale::kFixed && m.resolution > 0 ? ", step " + FormatNumber(m.resolution)
                                                    : std::string()) +
      " | " + (required ? "yes" : (m.workspace_only ? "no (workspace only)" : "no")) + " | " +
      doc_cell + " |\n";
}

template <class P>
void MarkdownRows(const P& p, const std::string& prefix, TableText* out);

/// The rows of one alternative of a list entry under `path` ("training[]"): a block alternative
/// (kBlock) first gets a row of its own, `training[].monte_carlo`.
template <class A>
void AlternativeRows(const std::string& path, TableText* out) {
  if constexpr (requires { A::kBlock; }) {
    const std::string at = path + "." + std::string(A::kBlock.key);
    Row(at, "map", "-", "", "", Meta{}, false,
        "An entry written as a single-key map {" + std::string(A::kBlock.key) + ": {...}}. " +
            std::string(A::kBlock.doc),
        out);
    MarkdownRows(A{}, at, out);
  } else {
    MarkdownRows(A{}, path, out);
  }
}
template <class E, std::size_t... I>
void AlternativesRows(const std::string& path, TableText* out, std::index_sequence<I...>) {
  (AlternativeRows<std::variant_alternative_t<I, E>>(path, out), ...);
}

/// The rows of MarkdownTable for the fields of `p`, keys prefixed with `prefix`.
template <class P>
void MarkdownRows(const P& p, const std::string& prefix, TableText* out) {
  ForEachField(
      p,
      [&](const std::string& path, const auto& value, const Meta& m) {
        using T = std::decay_t<decltype(value)>;
        using U = UnoptionalT<T>;
        const bool required = !m.optional && !kIsOptional<T>;
        if constexpr (kIsStruct<U>) {
          // A std::optional group: one row for it, then its fields (required when it is given).
          Row(path, "map", "-", DefaultCell(value), "", m, false,
              "Optional section; when given, every key below marked required must be given.", out);
          MarkdownRows(U{}, path, out);
        } else {
          Row(path, TypeName<T>(), m.unit, DefaultCell(value), BoundsCell<U>(m), m, required, m.doc,
              out);
          // A list's entry fields follow it as `key[].field`, with the entry's defaults; a map's
          // struct values as `key.<key>.field`.
          if constexpr (kIsList<U>) {
            using E = typename U::value_type;
            if constexpr (kIsVariant<E>)
              AlternativesRows<E>(path + "[]", out,
                                  std::make_index_sequence<std::variant_size_v<E>>{});
            else
              MarkdownRows(E{}, path + "[]", out);
          } else if constexpr (kIsMap<U>) {
            using V = typename U::value_type::second_type;
            if constexpr (kIsStruct<V>) MarkdownRows(V{}, path + ".<key>", out);
          }
        }
      },
      prefix);
}

}  // namespace detail

/// One row per field: key, type, unit, default, bounds, tuning scale (with the resolution of tuned
/// values, "log, step 0.01"), required, description. A list (`v.List`) is one row, followed by
/// one row per field of its entries (`parameters[].lo`; a variant entry's block alternative as
/// `training[].monte_carlo` and its fields); a map of structs (`v.Map`) one row followed by its
/// values' fields (`vary.<key>.uniform`); a std::optional group one row followed by its fields.
/// A description or default longer than detail::kMaxCell keeps its lead in the table and follows
/// it in full, one list item per key, under the table.
template <class P>
std::string MarkdownTable(const P& defaults = P{}) {
  detail::TableText out;
  out.rows =
      "| Key | Type | Unit | Default | Bounds | Tuning | Required | Description |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  detail::MarkdownRows(defaults, "", &out);
  if (out.notes.empty()) return out.rows;
  return out.rows + "\nIn full:\n\n" + out.notes;
}

}  // namespace scw::params
