// AC3D (.ac, and TORCS's .acc variant) reading: oovr's own parser, because
// TORCS files carry several `texture` lines per object (base, tiled, skids,
// shad layers; only the first, the base texture, is drawn), vertex normals on
// the vertex lines and several texture-coordinate pairs per surface reference.
//
// Each OBJECT of type poly with polygon surfaces becomes one object (one
// draw); its transform is the product of its and its parents' loc and rot.
// Textures are found through a search path and de-duplicated by file, so all
// objects naming one image share one texture.
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/scene.h"

namespace oovr {

struct Ac3dOptions {
  std::vector<std::string> texture_dirs;  // searched in order; empty = the file's directory
};

// Parses AC3D text. Throws Error naming the file, line and problem.
Scene parse_ac3d(const std::string& text, const std::string& name, const Ac3dOptions& options);
Scene load_ac3d_file(const std::string& path, const Ac3dOptions& options);

}  // namespace oovr
