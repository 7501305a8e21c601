// Streaming CSV output with an atomic finish: rows go through params::AtomicWriter as they are
// produced (memory stays flat whatever the run length): for a regular target into a temporary file
// next to it, which Commit() flushes, syncs and renames into place; a symlink's target is written
// the same way; a character device, FIFO or `-` (standard output) is written directly. A writer
// destroyed without Commit() removes its temporary file, so a crashed or aborted run never leaves
// a half-written file under the target name (and Ctrl-C removes it too: atomic_writer.h).
// Numbers are written with the shortest round-trip text (bit-exact when read back); text fields
// and header names are quoted per RFC 4180 when they contain ',', '"', CR or LF (tuning/io/csv.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "params/io/atomic_writer.h"

namespace scw::tuning {

class CsvWriter {
 public:
  /// Opens the target (see params::AtomicWriter) and writes the header. Throws std::runtime_error
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
  std::unique_ptr<params::AtomicWriter> file_;
  std::size_t columns_ = 0, in_row_ = 0, rows_ = 0;
  std::string error_;  ///< first write error (reported by Commit)
  std::string row_;
};

}  // namespace scw::tuning
