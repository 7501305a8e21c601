#include "params/io/csv.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "params/io/text.h"
#include "params/schema/field.h"

namespace scw::io {

namespace {

bool IsBlank(char c) { return kBlanks.find(c) != std::string_view::npos; }

/// "\n" or "\r\n" at `i`; a lone '\r' is data (or a blank when trimming).
bool LineEndAt(std::string_view text, std::size_t i) {
  return text[i] == '\n' || (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n');
}

/// A malformed field: thrown by the tokenizer, worded with its context by each reader.
struct Malformed {
  std::size_t line;
  const char* what;
};

/// The tokenizer behind every reader: scans the field that starts at `*i` into `*field` and
/// stops at the ',' or line end after it (or the end of the text). `*line` counts the line
/// breaks inside a quoted field.
void ScanField(std::string_view text, std::size_t* i, std::size_t* line, bool trim,
               std::string* field) {
  const std::size_t n = text.size();
  std::size_t p = *i;
  if (trim)
    while (p < n && IsBlank(text[p]) && !LineEndAt(text, p)) ++p;
  if (p < n && text[p] == '"') {
    const std::size_t opened = *line;
    ++p;
    while (true) {
      if (p >= n) throw Malformed{opened, "a quoted field is not closed"};
      const char c = text[p++];
      if (c == '"') {
        if (p < n && text[p] == '"') {
          field->push_back('"');
          ++p;
          continue;
        }
        break;
      }
      if (c == '\n') ++*line;
      field->push_back(c);
    }
    if (trim)
      while (p < n && IsBlank(text[p]) && !LineEndAt(text, p)) ++p;
    if (p < n && text[p] != ',' && !LineEndAt(text, p))
      throw Malformed{*line, "text after the closing quote of a field"};
  } else {
    const std::size_t start = p;
    while (p < n && text[p] != ',' && !LineEndAt(text, p)) ++p;
    std::string_view cell = text.substr(start, p - start);
    if (trim) cell = Trim(cell);
    field->append(cell);
  }
  *i = p;
}

std::string Where(int line, const std::string& column) {
  return "line " + std::to_string(line) + ", column " + column;
}

/// Length of the valid UTF-8 sequence of two or more bytes at `text[i]`, 0 if there is none.
std::size_t Utf8SequenceAt(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    if (b == 0xE0) lo = 0xA0;  // overlong
    if (b == 0xED) hi = 0x9F;  // surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    if (b == 0xF0) lo = 0x90;  // overlong
    if (b == 0xF4) hi = 0x8F;  // above U+10FFFF
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Messages about a file's text

std::string Printable(std::string_view text, std::size_t max_bytes) {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto b = static_cast<unsigned char>(text[i]);
    const std::size_t n = b < 0x80 ? 1 : Utf8SequenceAt(text, i);
    if (i + std::max<std::size_t>(n, 1) > max_bytes) {
      out += "...";
      break;
    }
    if (n >= 2) {
      out.append(text.substr(i, n));
      i += n;
    } else if (n == 1 && b >= 0x20 && b != 0x7F) {
      out.push_back(static_cast<char>(b));
      ++i;
    } else {
      static constexpr char kHex[] = "0123456789ABCDEF";
      out += "\\x";
      out.push_back(kHex[b >> 4]);
      out.push_back(kHex[b & 0xF]);
      ++i;
    }
  }
  return out;
}

std::size_t NulByteLine(std::string_view text) noexcept {
  const std::size_t nul = text.find('\0');
  if (nul == std::string_view::npos) return 0;
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + nul, '\n'));
}

// ---------------------------------------------------------------------------------------------
// Fields

bool CsvNeedsQuotes(std::string_view field) noexcept {
  return field.find_first_of(",\"\r\n") != std::string_view::npos;
}

void AppendCsvField(std::string* out, std::string_view field) {
  if (!CsvNeedsQuotes(field)) {
    out->append(field);
    return;
  }
  out->push_back('"');
  for (char c : field) {
    if (c == '"') out->push_back('"');
    out->push_back(c);
  }
  out->push_back('"');
}

std::string CsvField(std::string_view field) {
  std::string out;
  AppendCsvField(&out, field);
  return out;
}

std::string CsvRecord(const std::vector<std::string>& fields) {
  std::string out;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) out.push_back(',');
    AppendCsvField(&out, fields[i]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// CsvWriter

CsvWriter::CsvWriter(std::string path, const std::vector<std::string>& header)
    : path_(std::move(path)),
      file_(std::make_unique<AtomicWriter>(path_)),
      columns_(header.size()) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (i) row_ += ',';
    AppendCsvField(&row_, header[i]);
  }
  row_ += '\n';
  Put(row_);
  row_.clear();
}

CsvWriter::~CsvWriter() = default;

void CsvWriter::Put(std::string_view text) {
  if (!error_.empty()) return;
  try {
    file_->Append(text);
  } catch (const std::exception& e) {
    error_ = e.what();
  }
}

void CsvWriter::Add(double v) {
  if (in_row_++) row_ += ',';
  if (std::isnan(v)) {
    row_ += "nan";
    return;
  }
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  row_.append(buf, r.ptr);
}

void CsvWriter::Add(int v) {
  if (in_row_++) row_ += ',';
  char buf[16];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  row_.append(buf, r.ptr);
}

void CsvWriter::Add(const std::string& text) {
  if (in_row_++) row_ += ',';
  AppendCsvField(&row_, text);
}

void CsvWriter::EndRow() {
  if (in_row_ != columns_) {
    // A row of the wrong width would shift every later column under the wrong name, silently.
    const std::size_t cells = in_row_;
    row_.clear();
    in_row_ = 0;
    throw std::logic_error("CsvWriter " + path_ + ": row " + std::to_string(rows_ + 1) + " has " +
                           std::to_string(cells) + " cells, the header has " +
                           std::to_string(columns_) + " columns");
  }
  row_ += '\n';
  Put(row_);
  row_.clear();
  in_row_ = 0;
  ++rows_;
}

void CsvWriter::Commit() {
  if (!file_) throw std::runtime_error("cannot write " + path_ + ": the writer already failed");
  if (!error_.empty()) {
    file_.reset();  // removes the temporary file (already gone after a failed write)
    throw std::runtime_error(error_);
  }
  file_->Commit();
}

// ---------------------------------------------------------------------------------------------
// Reading

std::vector<std::vector<std::string>> ParseCsv(std::string_view text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  std::size_t line = 1;
  std::size_t i = 0;
  const std::size_t n = text.size();
  try {
    while (i < n) {
      ScanField(text, &i, &line, false, &field);
      record.push_back(std::move(field));
      field.clear();
      // The separator after it.
      if (i >= n) break;
      if (text[i] == ',') {
        ++i;
        if (i == n) record.emplace_back();  // "a," at the very end: a last, empty field
        continue;
      }
      i += text[i] == '\r' ? 2 : 1;  // line end
      ++line;
      records.push_back(std::move(record));
      record.clear();
    }
  } catch (const Malformed& m) {
    throw std::invalid_argument("CSV line " + std::to_string(m.line) + ": " + m.what);
  }
  if (!record.empty()) records.push_back(std::move(record));
  return records;
}

void SplitCsvLine(std::string_view line, std::vector<std::string>* cells, bool trim) {
  std::size_t k = 0, i = 0, line_no = 1;
  try {
    while (true) {
      if (cells->size() <= k) cells->emplace_back();
      std::string& cell = (*cells)[k++];
      cell.clear();
      ScanField(line, &i, &line_no, trim, &cell);
      if (i >= line.size() || line[i] != ',') break;
      ++i;
    }
  } catch (const Malformed& m) {
    throw std::invalid_argument(m.what);
  }
  cells->resize(k);
}

const std::vector<double>* CsvTable::Column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return &values[i];
  return nullptr;
}

CsvLog::CsvLog(std::string path, Open how, const std::vector<std::string>& header, std::string what)
    : path_(std::move(path)), what_(std::move(what)), columns_(header.size()) {
  if (how == Open::kAppend) {
    std::error_code ec;
    bytes_ = std::filesystem::file_size(path_, ec);
    if (ec) throw std::runtime_error("cannot read the size of " + what_ + " " + path_);
    file_.open(path_, std::ios::app | std::ios::binary);
    if (!file_) throw std::runtime_error("cannot append to " + what_ + " " + path_);
    return;
  }
  file_.open(path_, std::ios::trunc | std::ios::binary);
  if (!file_) throw std::runtime_error("cannot write " + what_ + " " + path_);
  const std::string head = CsvRecord(header) + '\n';
  file_ << head << std::flush;
  if (!file_) throw std::runtime_error("cannot write " + what_ + " " + path_);
  bytes_ = head.size();
}

bool CsvLog::Write(const std::vector<std::string>& row) {
  if (row.size() != columns_)
    throw std::logic_error(path_ + ": a row of " + std::to_string(row.size()) + " cells under " +
                           std::to_string(columns_) + " columns");
  if (!file_.is_open()) return false;
  const std::string line = CsvRecord(row) + '\n';
  file_ << line << std::flush;
  if (!file_) {
    // Disk full or similar: cut the log back to its last whole row, so that it stays a valid CSV
    // that can be continued.
    file_.close();
    std::error_code ec;
    std::filesystem::resize_file(path_, bytes_, ec);
    error_ = "writing " + what_ + " " + path_ + " failed";
    return false;
  }
  bytes_ += line.size();
  return true;
}

void CsvLog::Close() {
  if (file_.is_open()) file_.close();
}

CsvRowReader::CsvRowReader(const std::string& path) : file_(path, std::ios::binary) {
  if (!file_) return;
  {
    std::ifstream tail(path, std::ios::binary | std::ios::ate);
    const auto size = static_cast<long long>(tail.tellg());
    char last = '\n';
    if (size > 0) {
      tail.seekg(size - 1);
      tail.get(last);
    }
    ends_with_line_break_ = last == '\n';
  }
  std::getline(file_, header_);
}

CsvRowReader::Row CsvRowReader::Next(std::vector<std::string>* cells) {
  if (!file_.is_open() || !std::getline(file_, line_) || line_.empty()) return Row::kEnd;
  try {
    SplitCsvLine(line_, cells, false);
  } catch (const std::invalid_argument&) {
    return Row::kMalformed;
  }
  return Row::kCells;
}

CsvTable ReadCsvTable(const std::string& path, const std::vector<std::string>& required,
                      const std::vector<std::string>& optional) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(path, "", "is a directory, not a file");
  errno = 0;
  std::ifstream in(path);
  if (!in) {
    const int error = errno;
    throw ConfigError(
        path, "",
        "cannot open the file for reading" +
            (error != 0 ? " (" + std::string(std::strerror(error)) + ")" : std::string()));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return ParseCsvTable(text.str(), path, required, optional);
}

CsvTable ParseCsvTable(const std::string& text, const std::string& path,
                       const std::vector<std::string>& required,
                       const std::vector<std::string>& optional) {
  if (const std::size_t nul = NulByteLine(text))
    throw ConfigError(path, "line " + std::to_string(nul),
                      "a NUL byte: this is a binary file, not CSV text");
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  int header_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view t = Trim(line);
    if (t.empty()) continue;
    if (t.front() == '#') t = Trim(t.substr(1));
    try {
      SplitCsvLine(t, &header, true);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(path, "line " + std::to_string(line_no), e.what());
    }
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
                                        Printable(have, 80) + "'; expected columns " + expected +
                                        ")");
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
  std::vector<std::string> cells;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view t = Trim(line);
    if (t.empty() || t.front() == '#') continue;
    try {
      SplitCsvLine(t, &cells, true);
    } catch (const std::invalid_argument& e) {
      if (shown++ < 20) pr.Add("line " + std::to_string(line_no), e.what());
      continue;
    }
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
          problem = "'" + Printable(cell) + "' is not a number";
        else if (!std::isfinite(v))
          problem = "'" + Printable(cell) + "' is not a finite number";
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

}  // namespace scw::io
