// Workspace behaviour options of the stability controller (schema in
// params/schema/stability_options.h; every §10 quirk and its handling: docs/quirks.md).
#pragma once

#include "params/schema/stability_options.h"

namespace scw::controller {

using StabilityOptions = params::StabilityOptions;

/// long_fx as the slip controller sees it: 0 in release_compat mode (spec §1.5), else the input.
constexpr double EffectiveLongFx(const StabilityOptions& o, double long_fx) noexcept {
  return o.release_compat ? 0.0 : long_fx;
}

}  // namespace scw::controller
