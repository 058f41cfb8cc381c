// Levels of games built on the Quake 3 map format (Quake 3 BSP inside .pk3
// archives, shader scripts), drawn as their engine draws them: OpenArena
// through ioquake3's renderer, Nexuiz through DarkPlaces. Each game's
// source (sources/openarena.cpp, sources/nexuiz.cpp) says which engine and
// where its archives are.
//
// What an object is: the paper's objects are draw calls. A Quake 3 engine
// draws a map's surfaces sorted and merged by shader and lightmap, so by
// default every (shader, lightmap) pair is one surface group, drawn as one
// object per pass of its material ("group=shader-lightmap"). "group=face"
// makes every BSP surface its own group instead (many small draws, as a
// naive engine would issue them).
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/scene.h"
#include "oovr/scene/source.h"

namespace oovr {

// The renderer a game's levels are drawn as.
//  - ioquake3: every shader stage a pass, stages 0 and 1 collapsed into one
//    multitexture pass where CollapseMultitexture allows; lightmaps from
//    the BSP, overbright-shifted at load (x4, r_mapOverBrightBits 2).
//  - darkplaces: as ioquake3 for the shader stages, but a lightmapped
//    surface's lightmap x diffuse pass is DarkPlaces' one per-pixel lit pass
//    (Shading::deluxe: diffuse, _norm, _gloss, _glow, lightmap, deluxe)
//    when the map has deluxe maps; lightmaps from the BSP or, for maps
//    compiled with q3map2 -external, maps/<map>/lm_NNNN.tga, copied
//    unchanged (DarkPlaces' Mod_Q3BSP_LoadLightmaps).
enum class Q3Engine { ioquake3, darkplaces };

struct Q3Game {
  std::string prefix;     // scene name prefix, "oa"
  std::string title;      // "OpenArena"
  std::string directory;  // the game directory holding the .pk3 archives
  Q3Engine engine = Q3Engine::ioquake3;
};

struct Q3LevelOptions {
  enum class Group { shader_lightmap, face };
  Group group = Group::shader_lightmap;
  int tessellation = 4;  // segments per side of each 3x3 Bezier patch (1 to 16)
  // "materials=one-pass": every group drawn with one opaque pass, its
  // shader's first image times its lightmap, as oovr drew these levels
  // before real materials (the paper comparison's one-pass workloads).
  bool one_pass = false;
};

// Reads the options every Quake 3 level takes (group, tess, materials);
// Error for any other.
Q3LevelOptions parse_q3_level_options(const std::string& spec, const SceneOptions& options);

// Map names (without "maps/" and ".bsp") in the game directory's archives,
// sorted; empty when the directory does not exist.
std::vector<std::string> list_q3_maps(const Q3Game& game);
// The listing of every map, for a source's `list`.
std::vector<SceneListing> q3_listings(const Q3Game& game, const std::string& kind);
// Loads maps/<map>.bsp. Throws Error naming what is wrong.
Scene load_q3_level(const Q3Game& game, const std::string& map, const Q3LevelOptions& options);

// Quake units to metres (1 unit = 1 inch).
constexpr float kQuakeUnit = 0.0254f;

}  // namespace oovr
