// Moving average over the last N samples in a ring buffer of fixed capacity (stability-control
// spec Appendix A, used by the ABS safety limiter §3.4 step 6).
//
//   buffer of length N (1 ≤ N ≤ kCapacity), zero-initialised; Push overwrites the oldest sample;
//   Mean = (sum of all N slots) / N — zeros count until the buffer has filled once.
//
// Allocation-free: storage is a std::array of kCapacity. The window length N is a parameter held
// by the (immutable) controller and passed on every call, so a default-constructed buffer is a
// valid initial state for any N. N is clamped to [1, kCapacity]; a caller must keep N constant
// for one buffer (the controller validates N ≤ kCapacity at construction). Mean sums the N slots
// exactly on every call (no running sum, hence no drift); callers evaluate it only when needed.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

namespace scw::controller {

template <std::size_t kCapacity>
class RingBufferMean {
  static_assert(kCapacity >= 1);

 public:
  static constexpr std::size_t capacity() { return kCapacity; }

  void Push(double x, std::size_t length) noexcept {
    const std::size_t n = Clamp(length);
    if (next_ >= n) next_ = 0;
    data_[next_] = x;
    next_ = (next_ + 1 == n) ? 0 : next_ + 1;
  }

  double Mean(std::size_t length) const noexcept {
    const std::size_t n = Clamp(length);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += data_[i];
    return sum / static_cast<double>(n);
  }

 private:
  static std::size_t Clamp(std::size_t n) { return std::clamp<std::size_t>(n, 1, kCapacity); }
  std::array<double, kCapacity> data_{};
  std::size_t next_ = 0;
};

}  // namespace scw::controller
