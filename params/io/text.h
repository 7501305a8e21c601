// Small text helpers shared by the readers of command-line specs and plain-text files.
//
// Trim(s): `s` without leading and trailing blanks, where a blank is ' ', '\t' or '\r' (a CR is
// what remains of a "\r\n" line end after std::getline). Other bytes, '\n' included, are kept.
// The result views `s`: keep the text it came from alive while the view is used.
#pragma once

#include <string_view>

namespace scw::io {

/// The characters Trim() removes.
inline constexpr std::string_view kBlanks = " \t\r";

inline std::string_view Trim(std::string_view s) noexcept {
  const std::size_t b = s.find_first_not_of(kBlanks);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(kBlanks) - b + 1);
}

}  // namespace scw::io
