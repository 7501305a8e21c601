// The tracks the product defines itself (no data file needed), selected by name: a scenario's
// `track:` key and `scw track info|line --track` accept these names besides file paths.
//
//   "yas_north"  Yas Marina North (A2RL layout, ≈3.0 km, anticlockwise): the default
//                (plant/track/yas_north.h)
//   "monza"      Autodromo Nazionale Monza, 5.793 km Grand Prix layout, clockwise
//                (plant/track/monza.h)
//
// Names are lower case and carry no file extension, so they never collide with a *.yaml, *.yml
// or *.csv track file.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "plant/track/track.h"

namespace scw::plant {

/// The built-in track called `name`, or nothing when no built-in track has that name.
std::optional<Track> BuiltInTrack(std::string_view name);

/// The accepted names, comma separated, for help texts and error messages ("yas_north, monza").
std::string BuiltInTrackNames();

}  // namespace scw::plant
