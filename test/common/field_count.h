// The number of members of an aggregate, found at compile time by brace-initialising it with ever
// more arguments that convert to anything. Tests compare it with the number of members a
// struct's Visit lists, so a member added without its description fails a test.
#pragma once

#include <cstddef>
#include <utility>

namespace scw::test {

/// Converts to any member type (but never to the aggregate itself, which would count as a copy).
template <class Aggregate>
struct AnyMember {
  template <class T, class = std::enable_if_t<!std::is_same_v<std::decay_t<T>, Aggregate>>>
  operator T() const;  // declared only: used in unevaluated contexts
};

template <class T, std::size_t... I>
constexpr bool BraceConstructible(std::index_sequence<I...>) {
  return requires { T{(void(I), AnyMember<T>{})...}; };
}

/// Largest N ≤ 64 such that T{a1, …, aN} compiles: the member count of an aggregate whose
/// members are not themselves brace-elided (arrays and nested aggregates count as one member
/// when each is initialised from one value, which AnyMember provides).
template <class T, std::size_t N = 64>
constexpr std::size_t FieldCount() {
  if constexpr (N == 0) {
    return 0;
  } else if constexpr (BraceConstructible<T>(std::make_index_sequence<N>{})) {
    return N;
  } else {
    return FieldCount<T, N - 1>();
  }
}

}  // namespace scw::test
