#include "params/io/docs.h"

#include <cmath>

namespace scw::params::detail {

std::string BoundsText(double lo, double hi) {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  std::string out;
  if (has_lo && has_hi) {
    out.append("[").append(FormatNumber(lo)).append(", ").append(FormatNumber(hi)).append("]");
  } else if (has_lo) {
    out.append(">= ").append(FormatNumber(lo));
  } else if (has_hi) {
    out.append("<= ").append(FormatNumber(hi));
  }
  return out;
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
