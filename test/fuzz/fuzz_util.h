// Helpers shared by the libFuzzer targets of test/fuzz (see README.md there).
//
// Each target feeds one input through a loader exactly as the `scw` program does and treats
// scw::ConfigError (and its subclasses) as the only acceptable way to refuse an input. Any other
// exception escapes into libFuzzer ("deadly signal" / uncaught exception) and counts as a finding,
// as do sanitizer reports, timeouts and out-of-memory. Accepted inputs are additionally checked
// for the properties the workspace promises (an exported file loads back to the same values, …);
// a violated property throws PropertyViolation (FUZZ_CHECK), which libFuzzer reports as a crash.
//
// Built with -DSCW_FUZZ_MAIN (test/fuzz/CMakeLists.txt) each file also defines libFuzzer's entry
// point LLVMFuzzerTestOneInput; without it the targets are plain functions (fuzz_targets.h).
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#define FUZZ_CHECK(cond, what)                                                                   \
  do {                                                                                           \
    if (!(cond))                                                                                 \
      throw ::scw::fuzz::PropertyViolation(std::string(__FILE__) + ":" +                         \
                                           std::to_string(__LINE__) + ": " #cond ": " + (what)); \
  } while (0)

#ifdef SCW_FUZZ_MAIN
#define SCW_FUZZ_ENTRY(fn)                                                            \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return fn(data, size);                                                            \
  }
#else
#define SCW_FUZZ_ENTRY(fn)
#endif

namespace scw::fuzz {

/// A promised property of an accepted input does not hold.
class PropertyViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

inline std::string AsText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// An anonymous in-memory file (memfd) reachable by a path, for readers that take a file name:
/// no disk traffic and nothing left behind. One per process, rewritten for every input.
class MemFile {
 public:
  MemFile() {
    fd_ = ::memfd_create("scw-fuzz", 0);
    if (fd_ < 0) throw std::runtime_error("memfd_create failed");
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemFile() { ::close(fd_); }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;

  /// Replaces the content and returns the path.
  const std::string& Write(const std::uint8_t* data, std::size_t size) {
    if (::ftruncate(fd_, 0) != 0) std::abort();
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
      if (n <= 0) std::abort();
      done += static_cast<std::size_t>(n);
    }
    return path_;
  }

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace scw::fuzz
