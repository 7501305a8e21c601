// Controller state described once. Every mutable `State` struct of the controllers lists each of
// its members exactly once in
//
//   template <class Self, class V> static void Visit(Self& s, V& v);   // Self = State or const
//
// calling, per member, one of
//   v.Real(x)          a real that must stay finite (filters, integrators, latched values)
//   v.Reals(wheels)    four such reals (PerWheel<double>)
//   v.Time(t)          a time stamp [s]; −∞ means "never", NaN is invalid
//   v.Discrete(x)      an enum, bool or integer (no finiteness to check)
//   v.Buffer(b)        a RingBufferMean (its samples are checked through the outputs)
//   v.Nested(sub)      a nested State with its own Visit
//   v.NestedEach(ws)   a PerWheel of nested States
// The stability controller's state guard (StateFinite) is one visitor over this description, and
// test/controller/stability/state_visit_test.cc counts each struct's members against its Visit,
// so a member added without a line here fails a test instead of escaping the guard.
#pragma once

#include <cmath>

namespace scw::controller {

/// True while every Real and Reals is finite and no Time is NaN (recursing into nested
/// states). Allocation-free, noexcept.
class FiniteStateCheck {
 public:
  bool ok() const noexcept { return ok_; }
  void Real(double x) noexcept { ok_ = ok_ && std::isfinite(x); }
  template <class W>
  void Reals(const W& w) noexcept {
    for (double x : w) Real(x);
  }
  void Time(double t) noexcept { ok_ = ok_ && !std::isnan(t); }
  template <class T>
  void Discrete(const T&) noexcept {}
  /// Not scanned: a sample enters the buffer in the step whose output uses its mean, so a
  /// non-finite one already fails the output check; scanning 2 × 4 × 256 samples every step
  /// would cost more than the whole rest of the guard.
  template <class B>
  void Buffer(const B&) noexcept {}
  template <class S>
  void Nested(const S& s) noexcept {
    S::Visit(s, *this);
  }
  template <class W>
  void NestedEach(const W& w) noexcept {
    for (const auto& s : w) Nested(s);
  }

 private:
  bool ok_ = true;
};

/// Whether every checked member of `s` (a State with a Visit) is valid.
template <class S>
bool StateFinite(const S& s) noexcept {
  FiniteStateCheck check;
  S::Visit(s, check);
  return check.ok();
}

}  // namespace scw::controller
