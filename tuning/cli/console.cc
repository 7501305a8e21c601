#include "tuning/cli/console.h"

#include <algorithm>
#include <cctype>
#include <sstream>
#include <vector>

namespace scw::cli {
namespace {

bool IsRow(const std::string& line) {
  return line.size() >= 2 && line.front() == '|' && line.back() == '|';
}

std::vector<std::string> Cells(const std::string& row) {
  std::vector<std::string> cells;
  std::string cur;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|') {
      const auto b = cur.find_first_not_of(' ');
      const auto e = cur.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cur.substr(b, e - b + 1));
      cur.clear();
    } else {
      cur += row[i];
    }
  }
  return cells;
}

bool IsSeparator(const std::vector<std::string>& cells) {
  return !cells.empty() && std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
    return !c.empty() && c.find_first_not_of("-:") == std::string::npos;
  });
}

/// Characters on the screen (UTF-8 continuation bytes do not count).
std::size_t Width(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(
      s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

/// A number, a dash for "none", or numbers joined by '/' ("0/13/0/0").
bool IsNumeric(const std::string& s) {
  if (s == "-") return true;
  if (s.empty()) return false;
  bool digit = false;
  for (char c : s) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      digit = true;
      continue;
    }
    if (c != '.' && c != '-' && c != '+' && c != '/' && c != 'e') return false;
  }
  return digit;
}

void EmitTable(const std::vector<std::vector<std::string>>& rows, std::ostringstream& out) {
  std::size_t n = 0;
  for (const auto& r : rows) n = std::max(n, r.size());
  std::vector<std::size_t> width(n, 3);
  std::vector<bool> numeric(n, true);
  std::vector<bool> any(n, false);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (k == 1 && IsSeparator(rows[k])) continue;
    for (std::size_t c = 0; c < rows[k].size(); ++c) {
      width[c] = std::max(width[c], Width(rows[k][c]));
      if (k > 0) {
        numeric[c] = numeric[c] && IsNumeric(rows[k][c]);
        any[c] = true;
      }
    }
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    out << '|';
    for (std::size_t c = 0; c < n; ++c) {
      const bool right = numeric[c] && any[c];
      std::string cell = c < rows[k].size() ? rows[k][c] : "";
      if (k == 1 && IsSeparator(rows[k])) {
        cell = std::string(width[c] - (right ? 1 : 0), '-') + (right ? ":" : "");
      } else {
        const std::string pad(width[c] - std::min(width[c], Width(cell)), ' ');
        cell = right ? pad + cell : cell + pad;
      }
      out << ' ' << cell << " |";
    }
    out << '\n';
  }
}

}  // namespace

std::string AlignMarkdownTables(const std::string& markdown) {
  std::ostringstream out;
  std::istringstream in(markdown);
  std::vector<std::vector<std::string>> table;
  std::string line;
  while (std::getline(in, line)) {
    if (IsRow(line)) {
      table.push_back(Cells(line));
      continue;
    }
    if (!table.empty()) EmitTable(table, out);
    table.clear();
    out << line << '\n';
  }
  if (!table.empty()) EmitTable(table, out);
  std::string s = out.str();
  // Keep the input's (lack of a) final line break.
  if (!markdown.empty() && markdown.back() != '\n' && !s.empty()) s.pop_back();
  return s;
}

}  // namespace scw::cli
