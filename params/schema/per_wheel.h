// Per-wheel quantities. Wheel order everywhere in the workspace: FL = 0, FR = 1, RL = 2, RR = 3
// (stability-control spec §0.2). A plain std::array so it is trivially copyable, allocation-free
// and usable in hot paths of the controller and the plant alike.
#pragma once

#include <array>
#include <cstddef>

namespace scw {

template <class T>
using PerWheel = std::array<T, 4>;

enum Wheel : std::size_t { kFL = 0, kFR = 1, kRL = 2, kRR = 3 };

inline constexpr std::array<const char*, 4> kWheelNames = {"fl", "fr", "rl", "rr"};

inline constexpr bool IsFront(std::size_t i) { return i < 2; }
inline constexpr bool IsLeft(std::size_t i) { return i % 2 == 0; }

/// (front, front, rear, rear)
template <class T>
constexpr PerWheel<T> FromFrontRear(T front, T rear) {
  return {front, front, rear, rear};
}
/// (left, right, left, right)
template <class T>
constexpr PerWheel<T> FromLeftRight(T left, T right) {
  return {left, right, left, right};
}

}  // namespace scw
