#include "tuning/csv_writer.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "tuning/io/csv.h"

namespace scw::tuning {

CsvWriter::CsvWriter(std::string path, const std::vector<std::string>& header)
    : path_(std::move(path)),
      file_(std::make_unique<params::AtomicWriter>(path_)),
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

}  // namespace scw::tuning
