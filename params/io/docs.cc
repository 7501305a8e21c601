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

std::string Lead(const std::string& cell) {
  constexpr std::size_t kLead = 200;
  const std::size_t stop = cell.find(". ");
  if (stop != std::string::npos && stop + 1 <= kLead) return cell.substr(0, stop + 1);
  std::size_t cut = cell.rfind(' ', kLead);
  if (cut == std::string::npos || cut == 0) {
    cut = kLead;  // one long word: cut it, but not inside a UTF-8 sequence
    while (cut > 0 && (static_cast<unsigned char>(cell[cut]) & 0xC0) == 0x80) --cut;
  }
  return cell.substr(0, cut) + " …";
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
