#include "plant/track/builtin_tracks.h"

#include "plant/track/monza.h"
#include "plant/track/yas_north.h"

namespace scw::plant {

std::optional<Track> BuiltInTrack(std::string_view name) {
  if (name == "yas_north") return YasNorthTrack();
  if (name == "monza") return MonzaTrack();
  return std::nullopt;
}

std::string BuiltInTrackNames() { return "yas_north, monza"; }

}  // namespace scw::plant
