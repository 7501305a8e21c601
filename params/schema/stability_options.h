// Workspace behaviour options of the stability controller: choices that are NOT keys of the car's
// node file (so they are never exported to ROS 2) but decide how the workspace treats a documented
// quirk of the reference (stability-control spec §10, docs/quirks.md). Scenario files embed this
// struct; the defaults give the behaviour the system was designed for, each option says what the
// released node does instead.
#pragma once

#include "params/schema/field.h"

namespace scw::params {

struct StabilityOptions {
  /// Spec §1.5 / §10.2 #1. false: `long_fx` (requested total longitudinal force) is taken from
  /// the controller input (wired from the longitudinal controller's force request). true: the
  /// released node, where the setter is never called and long_fx ≡ 0 (TC can never activate, ABS
  /// only through the ESC trigger; the TC throttle cut still works).
  bool release_compat = false;

  /// Spec §10.2 #24. false (reference): the gear flank detectors start at gear 0, so the first
  /// non-zero engaged gear / gear request counts as a change (rear ABS/TC blocked for
  /// activation_time_after_gearshift and one rear pressure-reduction window at start-up).
  /// true: the first gear values seen initialise the detectors without counting as a change.
  bool ignore_initial_gear_change = false;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.release_compat,
            {.key = "release_compat",
             .doc = "Reproduce the released node: long_fx forced to 0 inside the controller (TC "
                    "cannot activate, ABS only via ESC). Default false: long_fx from the input.",
             .optional = true,
             .workspace_only = true});
    v.Field(s.ignore_initial_gear_change,
            {.key = "ignore_initial_gear_change",
             .doc = "Do not count the first gear value seen as a gear change (the reference "
                    "does: one rear ABS/TC cooldown and one rear pressure-reduction window at "
                    "start-up). Default false: reproduce the reference.",
             .optional = true,
             .workspace_only = true});
  }
};

}  // namespace scw::params
