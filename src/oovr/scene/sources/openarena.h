// OpenArena maps (Quake 3 BSP inside .pk3 archives) as oovr scenes, drawn as
// ioquake3's renderer draws them (sources/q3_level.h): "oa:MAP".
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/sources/q3_level.h"

namespace oovr {

// The game directory holding the .pk3 archives: $OOVR_OPENARENA_DIR, else
// Debian's /usr/share/games/openarena/baseoa.
std::string openarena_directory();
Q3Game openarena_game();
std::vector<std::string> list_openarena_maps();

}  // namespace oovr
