// Built-in second track: Autodromo Nazionale Monza, the 5.793 km Grand Prix layout, driven
// clockwise. Our own straights/arcs/clothoids definition (plant-and-track spec §5.4) built from
// public facts (length, corner radii) and fitted to the shape of the public OpenStreetMap centre
// line (racetrack-database, spec §5.4; only read to fit and check, nothing copied). The same
// definition is shipped as params/tracks/monza.yaml; a test checks that the file loads to exactly
// this value, so the product works without any file. It serves held-out scenarios on a track the
// tuner never sees.
//
// Layout (s from the start line on the main straight, curvature < 0 turns right):
//   main straight · Variante del Rettifilo (right-left, R 15-20 m) · Curva Grande (long right,
//   R ≥ 300 m) · Variante della Roggia (left-right, R 20-25 m) · Lesmo 1 (right, R 50-70 m) ·
//   Lesmo 2 (right, R 45-55 m) · Serraglio straight with its slight left kink · Variante Ascari
//   (left-right-left, R 50-100 m) · back straight · Parabolica / Curva Alboreto (right, R 80-100 m
//   at entry, opening onto the main straight).
// Width 12 m on the straights and Curva Grande, 11 m in Lesmo, Ascari and Parabolica, 10 m in the
// two chicanes. The segment table and the comparison with the public line are in the yaml file's
// header comment.
#pragma once

#include "params/schema/track_params.h"
#include "plant/track/track.h"

namespace scw::plant {

/// The piecewise definition (46 segments, start line at s = 0, frame of the public centre line:
/// x east, y north [m]). Total length 5793 m, total turning −2π; it closes by itself to < 1 mm.
params::TrackParams MonzaDefinition();

/// Track::FromDefinition(MonzaDefinition()).
Track MonzaTrack();

}  // namespace scw::plant
