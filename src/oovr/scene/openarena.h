// OpenArena maps (Quake 3 BSP inside .pk3 archives) as oovr scenes.
//
// What an object is: the paper's objects are draw calls. A Quake 3 engine
// draws a map's surfaces sorted and merged by shader and lightmap, so by
// default every (shader, lightmap) pair is one object, holding all the
// surfaces that use it ("group=shader-lightmap"). "group=face" makes every
// BSP surface its own object instead (many small draws, as a naive engine
// would issue them).
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/scene.h"

namespace oovr {

struct OpenArenaOptions {
  enum class Group { shader_lightmap, face };
  Group group = Group::shader_lightmap;
  int tessellation = 4;  // segments per side of each 3x3 Bezier patch (1 to 16)
};

// The game directory holding the .pk3 archives: $OOVR_OPENARENA_DIR, else
// Debian's /usr/share/games/openarena/baseoa.
std::string openarena_directory();
// Map names (without "maps/" and ".bsp") found in the game directory's
// archives, sorted; empty when the directory does not exist.
std::vector<std::string> list_openarena_maps();
// Loads maps/<map>.bsp. Throws Error naming what is wrong.
Scene load_openarena_map(const std::string& map, const OpenArenaOptions& options);

// Quake units to metres (1 unit = 1 inch).
constexpr float kQuakeUnit = 0.0254f;

}  // namespace oovr
