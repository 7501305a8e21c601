#include "params/io/docs.h"

#include <cmath>

namespace scw::params::detail {

std::string BoundsText(double lo, double hi) {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) return "[" + FormatNumber(lo) + ", " + FormatNumber(hi) + "]";
  if (has_lo) return "≥ " + FormatNumber(lo);
  if (has_hi) return "≤ " + FormatNumber(hi);
  return "";
}

std::string EscapeCell(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

const char* ScaleName(Scale s) {
  switch (s) {
    case Scale::kFixed:
      return "fixed";
    case Scale::kLinear:
      return "linear";
    case Scale::kLog:
      return "log";
  }
  return "?";
}

}  // namespace scw::params::detail
