// TORCS race tracks (Debian's torcs-data) as oovr scenes: the track's AC3D
// model (tracks/<category>/<name>/<name>.acc) with its textures (track
// directory, then data/textures and data/img, as TORCS searches), and a
// camera path along the track's centre line computed from the segments of
// its XML description (straights and arcs), at driver's eye height above the
// road surface found in the model.
#pragma once

#include <string>
#include <vector>

#include "oovr/core/math.h"
#include "oovr/scene/scene.h"

namespace oovr {

struct TorcsTrack {
  std::string name, category, directory;
};

// $OOVR_TORCS_DIR, else Debian's /usr/share/games/torcs.
std::string torcs_directory();
// Installed tracks that have a model, sorted by name.
std::vector<TorcsTrack> list_torcs_tracks();
Scene load_torcs_track(const std::string& name);

// The centre line of a track from its XML description, in oovr's frame
// (y up), one point per metre, and the start heading. Throws Error naming the
// file when the description has no usable segments.
std::vector<Vec3> torcs_centre_line(const std::string& xml_path);
// The same from the description's text (`xml_path` names it in messages;
// the fuzz target's entry point).
std::vector<Vec3> torcs_centre_line_from_text(const std::string& text, const std::string& xml_path);

}  // namespace oovr
