// Checks a model file before assimp reads it (docs/reliability.md): assimp
// trusts the sizes a file declares, so a 214-byte PLY claiming 2e9
// vertices grows past 14 GB, a truncated one can loop for ever, and a 2 KB
// GLB whose chunk says 2 GB allocates 2 GB. The counts and lengths a PLY
// header, a GLB container or a glTF document declares are checked against
// the bytes that are there and against InputLimits first; so are the
// groups and elements of an OBJ file, and the node instances a glTF node
// graph expands to (a node under two parents is drawn twice: 17 levels of
// two nodes sharing their children make 2^17 instances from 1.4 KB).
//
// What oovr does not draw is taken out of a glTF document before assimp
// sees it: skins, animations and morph targets (assimp 5.2's glTF 2
// importer crashes on a skin whose joint is its own mesh node).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/core/math.h"

namespace oovr {

// A PLY file's geometry, as oovr's own reader finds it: the first "vertex"
// element's x, y, z (s, t or u, v when given) and the "face" elements'
// vertex_indices, each polygon a fan of triangles.
struct PlyMesh {
  std::vector<Vec3> positions;
  std::vector<Vec2> uvs;
  std::vector<uint32_t> indices;
};
// Reads a PLY file's bytes (`name` for messages). Throws Error naming the
// file and what cannot be: a count the bytes do not hold, a face naming a
// vertex that is not there, a value that is not a number.
PlyMesh read_ply(const std::string& bytes, const std::string& name);

// Checks the bytes of model file `name` (for messages and its extension; a
// .gltf's external buffers are looked up beside it) and returns what assimp
// may read: the bytes, or the glTF/GLB without what oovr does not draw.
// Throws Error naming the file and the declared size that cannot be.
std::string precheck_model_bytes(const std::string& bytes, const std::string& name);

// Reads model file `path` (a regular file within InputLimits file_bytes)
// and checks it as above.
std::string precheck_model_file(const std::string& path);

}  // namespace oovr
