#include "params/io/test_fault.h"

#include <signal.h>

#include <cstdlib>
#include <iostream>
#include <mutex>
#include <string>

namespace scw::io {
namespace {

struct Fault {
  std::string point;
  long pass = 0;
  int signal = 0;
};

// Parses "POINT:K:SIGNAL"; an empty point when unset or invalid (then says so once).
Fault ReadFault() {
  Fault f;
  const char* v = std::getenv("SCW_TEST_FAULT");
  if (v == nullptr || *v == '\0') return f;
  const std::string text(v);
  const auto a = text.find(':');
  const auto b = a == std::string::npos ? a : text.find(':', a + 1);
  bool ok = a != std::string::npos && b != std::string::npos && a > 0;
  if (ok) {
    const std::string count = text.substr(a + 1, b - a - 1), sig = text.substr(b + 1);
    char* end = nullptr;
    const long k = count.empty() ? 0 : std::strtol(count.c_str(), &end, 10);
    const int s = sig == "INT" ? SIGINT : sig == "TERM" ? SIGTERM : sig == "KILL" ? SIGKILL : 0;
    ok = k >= 1 && end != nullptr && *end == '\0' && s != 0;
    if (ok) f = {text.substr(0, a), k, s};
  }
  if (!ok)
    std::cerr << "scw: warning: SCW_TEST_FAULT='" << text
              << "' is not POINT:K:SIGNAL (K >= 1; SIGNAL INT, TERM or KILL); ignored\n";
  return f;
}

}  // namespace

void TestFaultPoint(std::string_view point, long pass) {
  static std::once_flag once;
  static Fault fault;
  std::call_once(once, [] { fault = ReadFault(); });
  if (fault.signal != 0 && pass == fault.pass && point == fault.point) ::raise(fault.signal);
}

}  // namespace scw::io
