#include "tuning/io/csv.h"

#include <stdexcept>

namespace scw::tuning {

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

std::vector<std::vector<std::string>> ParseCsv(std::string_view text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  std::size_t line = 1;
  std::size_t i = 0;
  const std::size_t n = text.size();
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("CSV line " + std::to_string(line) + ": " + what);
  };
  while (i < n) {
    // One field.
    if (text[i] == '"') {
      const std::size_t opened = line;
      ++i;
      while (true) {
        if (i >= n) {
          line = opened;
          fail("a quoted field is not closed");
        }
        const char c = text[i++];
        if (c == '"') {
          if (i < n && text[i] == '"') {
            field.push_back('"');
            ++i;
            continue;
          }
          break;
        }
        if (c == '\n') ++line;
        field.push_back(c);
      }
      if (i < n && text[i] != ',' && text[i] != '\n' &&
          !(text[i] == '\r' && i + 1 < n && text[i + 1] == '\n'))
        fail("text after the closing quote of a field");
    } else {
      while (i < n && text[i] != ',' && text[i] != '\n' &&
             !(text[i] == '\r' && i + 1 < n && text[i + 1] == '\n'))
        field.push_back(text[i++]);
    }
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
  if (!record.empty()) records.push_back(std::move(record));
  return records;
}

}  // namespace scw::tuning
