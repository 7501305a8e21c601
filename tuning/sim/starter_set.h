// A starter scenario set for a track of the user's own (`scw scenarios init`): clean laps near the
// limit and the three critical situations of the event library placed at the track's corners, as
// `scw track info` numbers them (plant/track/corners.h), with held-out scenarios at other corners.
//
// Which corners (minor corners, plant::IsShortCorner / plant::IsKink, only when nothing else is
// left):
//   power_on        throttle fault of `value` 1.0 for 1.0 s, 20 m after the apex (the exit): the
//                   corners with the smallest radius first (slow exits, most drive torque).
//   late_braking    braking 20 m later than planned into the corner: the corners after the
//                   longest straight first (the highest entry speed).
//   rear_grip_loss  rear friction x 0.65 for 1.5 s from the apex: the corners with the largest
//                   radius first (the fastest corners).
// Each event takes the first `training_corners` of its ranking for training and the next
// `held_out_corners` (never one of its training corners) for the held-out scenarios, which also
// use other magnitudes (power-on 10 m after the apex, 0.8 s at 0.9; late braking 15 m; rear grip
// x 0.7), so the comparison sees situations the tuner did not. Clean laps: GG 1.1 and 1.2 for
// training, 1.15 held out. Every scenario is one lap on `track_ref`; critical ones may leave the
// line by 10 m before they abort (abort.max_lateral_error), as in the built-in set. The cost
// weights are the built-in default set's (ScenarioSet::Default().cost).
//
// Pure: no files. The caller reads the track and writes the set (tuning/cli/cmd_scenarios.cc).
#pragma once

#include <string>
#include <vector>

#include "plant/track/corners.h"
#include "plant/track/track.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {

struct StarterSetOptions {
  std::string name = "starter";  ///< the set's name
  std::string track_ref;         ///< the scenarios' `track` value, as the set file names it
  std::string vehicle_ref;       ///< the scenarios' `vehicle` value; "" = the built-in car
  int training_corners = 2;      ///< corners per critical event in training (>= 1)
  int held_out_corners = 1;      ///< corners per critical event held out (>= 0)
};

/// Where one kind of event went, and why there.
struct StarterEventPlaces {
  std::string event;              ///< "power_on", "late_braking", "rear_grip_loss"
  std::string rule;               ///< the ranking, as a person reads it
  std::vector<int> training;      ///< corner numbers
  std::vector<int> held_out;      ///< corner numbers
  std::vector<std::string> note;  ///< e.g. "no other corner left to hold out"
};

struct StarterSet {
  ScenarioSet set;
  std::vector<StarterEventPlaces> places;
  std::vector<plant::Corner> corners;  ///< every corner of the track, as numbered
  std::vector<int> minor;              ///< corners left out as short or kink (numbers)
};

/// The starter set of `track`. Throws scw::ConfigError when the track has no corner (a radius
/// below 250 m) or the options are out of range.
StarterSet MakeStarterSet(const plant::Track& track, const StarterSetOptions& options);

/// The set file's text: a comment block that says how it was made (track, corners per event and
/// why) and how to check it, then the set as ScenarioSet::ToYaml writes it.
std::string StarterSetYaml(const StarterSet& starter, const plant::Track& track);

}  // namespace scw::tuning
