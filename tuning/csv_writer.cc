#include "tuning/csv_writer.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace scw::tuning {

CsvWriter::CsvWriter(std::string path, const std::vector<std::string>& header)
    : path_(std::move(path)), columns_(header.size()) {
  static std::atomic<unsigned> counter{0};
  tmp_ = path_ + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (!file_) throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  buffer_.resize(1 << 16);
  std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (i) Put(",", 1);
    Put(header[i].data(), header[i].size());
  }
  Put("\n", 1);
}

CsvWriter::~CsvWriter() {
  if (file_) {
    std::fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void CsvWriter::Put(const char* text, std::size_t n) {
  if (n && std::fwrite(text, 1, n, file_) != n) failed_ = true;
}

void CsvWriter::Add(double v) {
  if (in_row_++) Put(",", 1);
  if (std::isnan(v)) return Put("nan", 3);
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  Put(buf, static_cast<std::size_t>(r.ptr - buf));
}

void CsvWriter::Add(int v) {
  if (in_row_++) Put(",", 1);
  char buf[16];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  Put(buf, static_cast<std::size_t>(r.ptr - buf));
}

void CsvWriter::Add(const std::string& text) {
  if (in_row_++) Put(",", 1);
  Put(text.data(), text.size());
}

void CsvWriter::EndRow() {
  Put("\n", 1);
  in_row_ = 0;
  ++rows_;
}

void CsvWriter::Commit() {
  if (!file_) throw std::runtime_error("cannot write " + path_ + ": already committed");
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (failed_ || !flushed || !closed || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp_.c_str());
    throw std::runtime_error("cannot write " + path_ + ": " + reason +
                             " (the previous file, if any, is unchanged)");
  }
}

}  // namespace scw::tuning
