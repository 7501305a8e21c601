#include "tuning/io/track_csv.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "params/schema/field.h"

namespace scw::tuning {

using plant::Track;
using plant::TrackBuildOptions;
namespace {

std::string Trim(std::string_view v) {
  while (!v.empty() && (v.front() == ' ' || v.front() == '\t' || v.front() == '\r'))
    v.remove_prefix(1);
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t' || v.back() == '\r'))
    v.remove_suffix(1);
  return std::string(v);
}

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(Trim(std::string_view(line).substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string Where(int line, const std::string& column) {
  return "line " + std::to_string(line) + ", column " + column;
}

}  // namespace

const std::vector<double>* CsvTable::Column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return &values[i];
  return nullptr;
}

CsvTable ReadCsvTable(const std::string& path, const std::vector<std::string>& required,
                      const std::vector<std::string>& optional) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, "", "cannot open the file for reading");
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  int header_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::string t = Trim(line);
    if (t.empty()) continue;
    if (t.front() == '#') t = Trim(std::string_view(t).substr(1));
    header = Split(t);
    header_line = line_no;
    break;
  }
  std::string expected;
  for (const auto& r : required) expected += (expected.empty() ? "" : ",") + r;
  if (header.empty())
    throw ConfigError(path, "", "the file is empty (expected a header " + expected + ")");

  CsvTable table;
  std::vector<std::size_t> index;
  Problems pr;
  auto find = [&](const std::string& name) -> long {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<long>(i);
    return -1;
  };
  for (const auto& r : required) {
    const long i = find(r);
    if (i < 0) {
      std::string have;
      for (const auto& h : header) have += (have.empty() ? "" : ",") + h;
      pr.Add(Where(header_line, r), "missing column '" + r + "' in the header (the header is '" +
                                        have + "'; expected columns " + expected + ")");
    } else {
      table.names.push_back(r);
      index.push_back(static_cast<std::size_t>(i));
    }
  }
  if (!pr.empty()) throw ConfigError(path, pr.items());
  for (const auto& o : optional) {
    const long i = find(o);
    if (i >= 0) {
      table.names.push_back(o);
      index.push_back(static_cast<std::size_t>(i));
    }
  }
  table.values.assign(table.names.size(), {});

  int shown = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = Trim(line);
    if (t.empty() || t.front() == '#') continue;
    const std::vector<std::string> cells = Split(t);
    table.lines.push_back(line_no);
    for (std::size_t c = 0; c < index.size(); ++c) {
      double v = std::numeric_limits<double>::quiet_NaN();
      std::string problem;
      if (index[c] >= cells.size()) {
        problem = "missing value (the row has " + std::to_string(cells.size()) + " cells, the " +
                  "header " + std::to_string(header.size()) + ")";
      } else {
        const std::string& cell = cells[index[c]];
        const char* b = cell.data();
        const char* e = b + cell.size();
        if (b != e && *b == '+') ++b;
        const auto res = std::from_chars(b, e, v);
        if (cell.empty())
          problem = "empty cell, expected a number";
        else if (res.ec != std::errc() || res.ptr != e)
          problem = "'" + cell + "' is not a number";
        else if (!std::isfinite(v))
          problem = "'" + cell + "' is not a finite number";
      }
      if (!problem.empty() && shown < 20) {
        pr.Add(Where(line_no, table.names[c]), problem);
        ++shown;
      }
      table.values[c].push_back(v);
    }
  }
  if (!pr.empty()) throw ConfigError(path, pr.items());
  return table;
}

Track LoadTrackCsv(const std::string& path, const TrackBuildOptions& options) {
  const CsvTable t =
      ReadCsvTable(path, {"x_m", "y_m", "w_tr_right_m", "w_tr_left_m"}, {"friction_scale"});
  const std::size_t rows = t.lines.size();
  if (rows < 8)
    throw ConfigError(path, "",
                      "too few rows for a closed track: " + std::to_string(rows) +
                          " data row(s), need at least 8");
  std::vector<double> wl(*t.Column("w_tr_left_m")), wr(*t.Column("w_tr_right_m"));
  Problems pr;
  for (std::size_t i = 0; i < rows; ++i) {
    wl[i] = std::abs(wl[i]);
    wr[i] = std::abs(wr[i]);
    if (wl[i] == 0.0) pr.Add(Where(t.lines[i], "w_tr_left_m"), "width must be non-zero");
    if (wr[i] == 0.0) pr.Add(Where(t.lines[i], "w_tr_right_m"), "width must be non-zero");
  }
  if (!pr.empty()) throw ConfigError(path, pr.items());
  const std::vector<double>* mu = t.Column("friction_scale");
  const std::string name = std::filesystem::path(path).stem().string();
  try {
    return Track::FromPoints(*t.Column("x_m"), *t.Column("y_m"), wl, wr,
                             mu ? *mu : std::vector<double>{}, options, name, path);
  } catch (const ConfigError& e) {
    // Name the source line for per-point problems ("point K" → "line L").
    std::vector<Problem> out;
    for (const auto& p : e.problems()) {
      Problem q = p;
      if (p.path.rfind("point ", 0) == 0) {
        const std::size_t k = std::stoul(p.path.substr(6));
        if (k < rows) q.path = "line " + std::to_string(t.lines[k]);
      } else if (p.message.find("does not close") != std::string::npos) {
        q.path = "line " + std::to_string(t.lines.back()) + " (last row) vs line " +
                 std::to_string(t.lines.front()) + " (first row)";
      }
      out.push_back(q);
    }
    throw ConfigError(path, out);
  }
}

}  // namespace scw::tuning
