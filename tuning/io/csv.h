// CSV text per RFC 4180, the dialect of every table scw writes (traces, sweep tables, comparison
// tables) and of the readers that check them:
//  * fields are separated by ',' and records end with '\n' (a reader also accepts "\r\n");
//  * a field that contains ',', '"', CR or LF is enclosed in double quotes, and each '"' inside
//    it is doubled: `He said "hi", then left` → `"He said ""hi"", then left"`;
//  * any other field is written as is (numbers, names without those characters), so files
//    without such text are byte-for-byte what they were before quoting existed.
// A scenario or configuration name with a comma therefore stays one cell instead of shifting
// every column after it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace scw::tuning {

/// Whether `field` must be quoted (contains ',', '"', CR or LF).
bool CsvNeedsQuotes(std::string_view field) noexcept;

/// Appends `field` to `*out`, quoted when CsvNeedsQuotes().
void AppendCsvField(std::string* out, std::string_view field);

/// `field` as one CSV cell (quoted when needed).
std::string CsvField(std::string_view field);

/// One record (fields joined by ',', each through CsvField), without the line end.
std::string CsvRecord(const std::vector<std::string>& fields);

/// Splits CSV text into records of unquoted fields. Quoted fields may hold commas, doubled
/// quotes and line breaks; a final line end is optional; a trailing empty line is no record.
/// Throws std::invalid_argument naming the line for a quote that is not closed or text after a
/// closing quote.
std::vector<std::vector<std::string>> ParseCsv(std::string_view text);

}  // namespace scw::tuning
