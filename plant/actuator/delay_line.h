// Pure transport delay of a fixed number of samples: a ring buffer whose capacity is set when it
// is built (never in the step), so pushing and reading allocate nothing.
//
// Contract: y[k] = u[k - n] for k >= n, y[k] = initial value before; n = 0 passes u through.
#pragma once

#include <cstddef>
#include <vector>

namespace scw::plant {

template <class T>
class DelayLine {
 public:
  DelayLine() = default;
  DelayLine(std::size_t samples, const T& initial) : buf_(samples, initial) {}

  /// Pushes u and returns the sample pushed `samples` calls ago.
  T Shift(const T& u) noexcept {
    if (buf_.empty()) return u;
    T out = buf_[head_];
    buf_[head_] = u;
    head_ = head_ + 1 == buf_.size() ? 0 : head_ + 1;
    return out;
  }
  /// Sets every stored sample (no allocation).
  void Fill(const T& value) noexcept {
    for (auto& b : buf_) b = value;
  }
  std::size_t samples() const noexcept { return buf_.size(); }

 private:
  std::vector<T> buf_;
  std::size_t head_ = 0;
};

}  // namespace scw::plant
