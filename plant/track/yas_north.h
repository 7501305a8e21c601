// The workspace's built-in default track: Yas Marina North (A2RL layout, ≈3.0 km, anticlockwise),
// our own straights/arcs/clothoids definition following the public centre line (plant-and-track
// spec §5.2). The same definition is shipped as params/tracks/yas_north.yaml; a test checks that
// the file loads to exactly this value, so the product works without any file.
#pragma once

#include "params/schema/track_params.h"
#include "plant/track/track.h"

namespace scw::plant {

/// The piecewise definition (32 segments, start line at s = 0, frame of the public Track3D data).
params::TrackParams YasNorthDefinition();

/// Track::FromDefinition(YasNorthDefinition()).
Track YasNorthTrack();

}  // namespace scw::plant
