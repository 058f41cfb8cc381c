// Nexuiz maps (Debian's nexuiz-data: Quake 3 BSP with external lightmaps
// and deluxe maps, textures with _norm, _gloss and _glow layers) as oovr
// scenes, drawn as DarkPlaces draws them (sources/q3_level.h): "nexuiz:MAP".
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/sources/q3_level.h"

namespace oovr {

// $OOVR_NEXUIZ_DIR, else Debian's /usr/share/games/nexuiz/data.
std::string nexuiz_directory();
Q3Game nexuiz_game();
std::vector<std::string> list_nexuiz_maps();

}  // namespace oovr
