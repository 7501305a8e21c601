// Streaming CSV output with an atomic finish: rows go to a temporary file next to the target as
// they are produced (memory stays flat whatever the run length); Commit() flushes, syncs and
// renames it into place. A writer destroyed without Commit() removes its temporary file, so a
// crashed or aborted run never leaves a half-written file under the target name.
// Numbers are written with the shortest round-trip text (bit-exact when read back).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace scw::tuning {

class CsvWriter {
 public:
  /// Opens `<path>.tmp.<pid>.<n>` and writes the header. Throws std::runtime_error naming the
  /// path if the file cannot be created.
  CsvWriter(std::string path, const std::vector<std::string>& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Appends one value to the current row (row ends with EndRow()).
  void Add(double v);
  void Add(int v);
  void Add(const std::string& text);
  void EndRow();
  std::size_t columns() const { return columns_; }
  std::size_t rows() const { return rows_; }
  const std::string& path() const { return path_; }

  /// Finishes the file and renames it to the target path. Throws std::runtime_error naming the
  /// path on any write error (the target then keeps its previous content).
  void Commit();

 private:
  void Put(const char* text, std::size_t n);
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
  std::size_t columns_ = 0, in_row_ = 0, rows_ = 0;
  bool failed_ = false;
  std::vector<char> buffer_;
};

}  // namespace scw::tuning
