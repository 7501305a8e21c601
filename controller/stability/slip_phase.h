// Phase of one ABS or TC wheel controller (stability-control spec §3.3). The integer values are
// the reference's and are what logs record: Inactive = 0, Reduce = 1, Hold = 2, Increase = 3.
// A wheel is "active" (latched) in every phase other than Inactive.
#pragma once

#include <cstdint>

namespace scw::controller {

enum class SlipPhase : std::uint8_t { kInactive = 0, kReduce = 1, kHold = 2, kIncrease = 3 };

constexpr int ToInt(SlipPhase p) { return static_cast<int>(p); }
constexpr bool IsActive(SlipPhase p) { return p != SlipPhase::kInactive; }

constexpr const char* Name(SlipPhase p) {
  switch (p) {
    case SlipPhase::kInactive:
      return "inactive";
    case SlipPhase::kReduce:
      return "reduce";
    case SlipPhase::kHold:
      return "hold";
    case SlipPhase::kIncrease:
      return "increase";
  }
  return "?";
}

}  // namespace scw::controller
