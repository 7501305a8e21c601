// The exact identity of a schema struct's value, derived from its Visit: one line per field,
// `path=value`, numbers in the shortest text that reads back to exactly the same double
// (FormatNumber), texts length-prefixed, list and map entries with their index or key, an absent
// optional as `-`. Two values have the same fingerprint if and only if every field is equal
// (bit for bit, up to the sign of zero and NaN payloads, which no validated struct holds), so
// it keys caches of results computed from the struct (the reference cache,
// controller/planning/reference_cache.h) without going through any file format.
#pragma once

#include <string>
#include <type_traits>
#include <variant>

#include "params/schema/field.h"

namespace scw::params {

namespace detail {

template <class T>
void AppendFingerprint(const std::string& path, const T& value, std::string* out);

template <class P>
void AppendStructFingerprint(const std::string& prefix, const P& p, std::string* out) {
  ForEachField(
      p,
      [out](const std::string& path, const auto& value, const Meta&) {
        AppendFingerprint(path, value, out);
      },
      prefix);
}

template <class T>
void AppendFingerprint(const std::string& path, const T& value, std::string* out) {
  using U = std::remove_cv_t<T>;
  if constexpr (kIsOptional<U>) {
    if (value)
      AppendFingerprint(path, *value, out);
    else
      *out += path + "=-\n";
  } else if constexpr (kIsVariant<U>) {
    *out += path + "#" + std::to_string(value.index()) + "\n";
    std::visit([&](const auto& alt) { AppendFingerprint(path, alt, out); }, value);
  } else if constexpr (kIsMap<U>) {
    for (const auto& [key, item] : value)
      AppendFingerprint(path + "{" + std::to_string(key.size()) + ":" + key + "}", item, out);
    *out += path + "#" + std::to_string(value.size()) + "\n";
  } else if constexpr (kIsVector<U>) {
    for (std::size_t i = 0; i < value.size(); ++i)
      AppendFingerprint(ListItemPath(path, i), value[i], out);
    *out += path + "#" + std::to_string(value.size()) + "\n";
  } else if constexpr (kIsStruct<U>) {
    AppendStructFingerprint(path, value, out);
  } else if constexpr (std::is_same_v<U, std::string>) {
    *out += path + "=" + std::to_string(value.size()) + ":" + value + "\n";
  } else if constexpr (std::is_same_v<U, bool>) {
    *out += path + (value ? "=true\n" : "=false\n");
  } else if constexpr (std::is_floating_point_v<U>) {
    *out += path + "=" + FormatNumber(static_cast<double>(value)) + "\n";
  } else {
    static_assert(std::is_integral_v<U> || std::is_enum_v<U>, "a field type Fingerprint knows");
    *out += path + "=" + std::to_string(static_cast<long long>(value)) + "\n";
  }
}

}  // namespace detail

/// The fingerprint of `p` (see the file comment); `prefix` goes before every path.
template <class P>
std::string Fingerprint(const P& p, const std::string& prefix = "") {
  std::string out;
  detail::AppendStructFingerprint(prefix, p, &out);
  return out;
}

}  // namespace scw::params
