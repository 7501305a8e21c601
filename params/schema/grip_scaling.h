// A scenario's grip factors applied to a vehicle's grip, and taken off again. A scenario's car is
// the vehicle file's with every friction scaling multiplied by the scenario's factor of the same
// key (grip.rear_mu_y = 0.8: "rear lateral grip -20 %"); a planner that plans with the nominal
// grip (plan_with_nominal_grip) divides them back out. Both walk GripParams::Visit, so a factor
// added to GripParams is scaled and unscaled without a further list.
//
// Per-wheel lists: element by element over the elements both lists have (a validated GripParams
// has exactly 4). Division by a factor inverts the multiplication up to one rounding per member
// (exactly for powers of two); the factors are bounded to [0.05, 2] by the schema.
#pragma once

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/tire_params.h"

namespace scw::params {

namespace detail {

/// grip_member = op(grip_member, factor_member) for every member of GripParams (the members of the
/// two structs are paired by their place in Visit, where both have the same type).
template <class Op>
void CombineGrip(const GripParams& factors, GripParams* grip, Op op) {
  std::vector<const void*> by_place;
  ForEachField(factors, [&](const std::string&, const auto& member, const Meta&) {
    by_place.push_back(&member);
  });
  std::size_t place = 0;
  ForEachField(*grip, [&](const std::string&, auto& member, const Meta&) {
    using T = std::remove_reference_t<decltype(member)>;
    const T& factor = *static_cast<const T*>(by_place[place++]);
    if constexpr (std::is_same_v<T, double>) {
      member = op(member, factor);
    } else {
      static_assert(std::is_same_v<T, std::vector<double>>, "a grip factor or a per-wheel list");
      for (std::size_t i = 0; i < member.size() && i < factor.size(); ++i)
        member[i] = op(member[i], factor[i]);
    }
  });
}

}  // namespace detail

/// Multiplies every friction scaling of `grip` by the factor of the same key in `factors`.
inline void ScaleGrip(const GripParams& factors, GripParams* grip) {
  detail::CombineGrip(factors, grip, [](double g, double f) { return g * f; });
}

/// The inverse of ScaleGrip: divides every friction scaling of `grip` by the factor of `factors`.
inline void UnscaleGrip(const GripParams& factors, GripParams* grip) {
  detail::CombineGrip(factors, grip, [](double g, double f) { return g / f; });
}

}  // namespace scw::params
