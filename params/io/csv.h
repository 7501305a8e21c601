// CSV, the one dialect of every table scw writes (traces, sweep tables, comparison tables, bench
// tables) and reads (track tables, controller logs, a tune's evaluation log). RFC 4180:
//  * fields are separated by ',' and records end with '\n' (readers also accept "\r\n");
//  * a field that contains ',', '"', CR or LF is enclosed in double quotes, and each '"' inside
//    it is doubled: `He said "hi", then left` → `"He said ""hi"", then left"`;
//  * any other field is written as is (numbers, names without those characters), so files
//    without such text are byte-for-byte what they were before quoting existed.
// A scenario or configuration name with a comma therefore stays one cell instead of shifting
// every column after it.
//
// Writing: CsvWriter streams rows through io::AtomicWriter (params/io/atomic_file.h): a regular
// target appears whole at Commit() or not at all, a device, FIFO or `-` is written directly.
// Numbers are written with the shortest round-trip text (bit-exact when read back), NaN as `nan`.
// CsvLog is the one exception to "whole or not at all": an append-only log (a tune's evaluation
// log) whose rows must survive an interrupted run, so each row is flushed as it is written and a
// row that does not fit is cut off again (the file always holds whole rows).
//
// Reading: ParseCsv (whole text, quoted fields may span lines), SplitCsvLine (one line, for
// streaming readers), CsvRowReader (a log row by row, as it is replayed) and ReadCsvTable /
// ParseCsvTable (numeric columns by name from a file, or its text, with a header, comment and blank
// lines) share one tokenizer. Blank = ' ', '\t', '\r' (params/io/text.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "params/io/atomic_file.h"

namespace scw::io {

// ---------------------------------------------------------------------------------------------
// Fields

/// Whether `field` must be quoted (contains ',', '"', CR or LF).
bool CsvNeedsQuotes(std::string_view field) noexcept;

/// Appends `field` to `*out`, quoted when CsvNeedsQuotes().
void AppendCsvField(std::string* out, std::string_view field);

/// `field` as one CSV cell (quoted when needed).
std::string CsvField(std::string_view field);

/// One record (fields joined by ',', each through CsvField), without the line end.
std::string CsvRecord(const std::vector<std::string>& fields);

// ---------------------------------------------------------------------------------------------
// Messages about a file's text

/// `text` as it may be quoted in a message: bytes a terminal would act on or show as garbage
/// (control characters, DEL, bytes that are not UTF-8) as `\xNN`, valid UTF-8 as it is; cut
/// after `max_bytes` bytes of `text` with "..." (a UTF-8 character is never split).
std::string Printable(std::string_view text, std::size_t max_bytes = 40);

/// The 1-based line of the first NUL byte of `text` (no text file has one: it is a binary file),
/// or 0 when there is none.
std::size_t NulByteLine(std::string_view text) noexcept;

// ---------------------------------------------------------------------------------------------
// Writing

/// A CSV file written row by row (memory stays flat whatever the run length). Every row must have
/// exactly as many cells as the header: EndRow() throws std::logic_error otherwise (a bug in the
/// caller, never bad input). Without Commit() the target keeps its previous content.
/// Not thread-safe (one writer per thread).
class CsvWriter {
 public:
  /// Opens the target (see io::AtomicWriter) and writes the header. Throws std::runtime_error
  /// naming the path if the file cannot be created.
  CsvWriter(std::string path, const std::vector<std::string>& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Appends one value to the current row (row ends with EndRow()). Never throws: a write error
  /// is reported by Commit().
  void Add(double v);
  void Add(int v);
  /// A text cell, written verbatim unless it needs RFC 4180 quoting. Pass raw text: a value that
  /// is already quoted would be quoted again.
  void Add(const std::string& text);
  /// Ends the row. Throws std::logic_error naming the file, the row (1 = first row after the
  /// header) and both counts when the row does not have columns() cells; nothing of that row is
  /// written.
  void EndRow();
  std::size_t columns() const { return columns_; }
  std::size_t rows() const { return rows_; }
  const std::string& path() const { return path_; }

  /// Finishes the file and renames it to the target path. Throws std::runtime_error naming the
  /// path on any write error (the target then keeps its previous content).
  void Commit();

 private:
  void Put(std::string_view text);
  std::string path_;
  std::unique_ptr<AtomicWriter> file_;
  std::size_t columns_ = 0, in_row_ = 0, rows_ = 0;
  std::string error_;  ///< first write error (reported by Commit)
  std::string row_;
};

/// An append-only CSV log (see the file comment): rows reach the file one by one, each flushed,
/// and a row that cannot be written whole is cut off again, so the file stays a valid CSV that a
/// reader (CsvRowReader) can continue from. Messages name the log as `what` (e.g. "the
/// evaluation log") and its path. Not thread-safe.
class CsvLog {
 public:
  enum class Open {
    kCreate,  ///< create or truncate the file and write the header
    kAppend,  ///< append after the rows already there (the caller has checked its header)
  };
  /// Throws std::runtime_error `cannot write <what> <path>` (kCreate), `cannot append to <what>
  /// <path>` or `cannot read the size of <what> <path>` (kAppend).
  CsvLog(std::string path, Open how, const std::vector<std::string>& header, std::string what);
  CsvLog(const CsvLog&) = delete;
  CsvLog& operator=(const CsvLog&) = delete;

  /// Writes one record and flushes it. Throws std::logic_error when the row does not have as many
  /// cells as the header (a bug in the caller). On a write error (disk full, …) the file is cut
  /// back to its last whole row and closed, error() says `writing <what> <path> failed`, and the
  /// result is false; every later call returns false.
  bool Write(const std::vector<std::string>& row);
  bool is_open() const { return file_.is_open(); }
  const std::string& error() const { return error_; }
  void Close();

 private:
  std::string path_, what_, error_;
  std::ofstream file_;
  std::size_t columns_ = 0;
  std::uintmax_t bytes_ = 0;  ///< size of the whole rows written so far
};

// ---------------------------------------------------------------------------------------------
// Reading

/// A CSV file read record by record (memory stays flat), for a log replayed as it is consumed.
/// One record per line (a quoted field cannot span lines here). Opening never throws: is_open()
/// says whether the file could be read.
class CsvRowReader {
 public:
  enum class Row {
    kEnd,        ///< no more records (end of file or an empty line)
    kCells,      ///< *cells holds the next record's unquoted, untrimmed fields
    kMalformed,  ///< the next line is no valid record (SplitCsvLine refused it)
  };
  explicit CsvRowReader(const std::string& path);
  bool is_open() const { return file_.is_open(); }
  /// The first line of the file as written (without its line break): the header.
  const std::string& header_line() const { return header_; }
  /// Whether the file ends with a line break (false for a file cut inside a row; true if empty).
  bool ends_with_line_break() const { return ends_with_line_break_; }
  /// Reads the next record (the line after the previous one).
  Row Next(std::vector<std::string>* cells);
  void Close() { file_.close(); }

 private:
  std::ifstream file_;
  std::string header_, line_;
  bool ends_with_line_break_ = true;
};

/// Splits CSV text into records of unquoted fields. Quoted fields may hold commas, doubled
/// quotes and line breaks; a final line end is optional; a trailing empty line is no record.
/// Nothing is trimmed. Throws std::invalid_argument `CSV line N: ...` for a quote that is not
/// closed or text after a closing quote.
std::vector<std::vector<std::string>> ParseCsv(std::string_view text);

/// Splits one line (without its '\n'; a "\r" left by getline counts as blank) into `*cells`,
/// reusing the strings already there. With `trim`, blanks around each field (and around the
/// quotes of a quoted one) are dropped. A line with n commas outside quotes gives n + 1 cells.
/// Throws std::invalid_argument (message without a line number: the caller knows it) for a quote
/// that is not closed on the line or text after a closing quote.
void SplitCsvLine(std::string_view line, std::vector<std::string>* cells, bool trim);

/// Numeric columns of a CSV file with a header line.
struct CsvTable {
  std::vector<std::string> names;           ///< requested columns (required then optional found)
  std::vector<std::vector<double>> values;  ///< values[column][row]
  std::vector<int> lines;                   ///< source line of each row (1-based)

  /// Column by name, or nullptr.
  const std::vector<double>* Column(const std::string& name) const;
};

/// Reads `path`: the first non-blank line is the header (a leading '#' is allowed), columns are
/// found by name in any order and extra ones are ignored; `required` columns must exist,
/// `optional` ones are read when present. Later comment lines (#) and blank lines are skipped.
/// Cells are trimmed and may be quoted. Throws scw::ConfigError naming the file with one problem
/// per bad cell as `line L, column C: message` (non-numeric, NaN/inf, empty, missing; up to 20),
/// per missing column, or per malformed line; a file with a NUL byte is one problem (a binary
/// file). Text of the file quoted in a message goes through Printable().
CsvTable ReadCsvTable(const std::string& path, const std::vector<std::string>& required,
                      const std::vector<std::string>& optional = {});
/// ReadCsvTable of a file's `text` already read; `path` names it in errors.
CsvTable ParseCsvTable(const std::string& text, const std::string& path,
                       const std::vector<std::string>& required,
                       const std::vector<std::string>& optional = {});

}  // namespace scw::io
