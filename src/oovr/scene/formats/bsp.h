// Quake 3 BSP (IBSP version 46) reading: oovr's own parser, written from the
// format's public description. Every offset, count and index in the file is
// checked once in parse_bsp, so the rest of the loader can trust the result;
// a truncated or corrupt file is an Error naming the file and the problem.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "oovr/core/math.h"

namespace oovr {

// Face types (the `type` field of a face).
enum BspFaceType : int { kBspPolygon = 1, kBspPatch = 2, kBspMesh = 3, kBspBillboard = 4 };
// Surface flags of the texture lump that matter here.
constexpr int32_t kSurfSky = 0x4;
constexpr int32_t kSurfNodraw = 0x80;
constexpr int kBspLightmapSize = 128;  // lightmaps are 128x128 RGB

struct BspShaderRef {
  std::string name;
  int32_t surface_flags = 0;
  int32_t contents = 0;
};

struct BspVertex {
  Vec3 position;  // Quake units, z up
  Vec2 st;        // surface texture coordinates
  Vec2 lm;        // lightmap coordinates
  Vec3 normal;
};

struct BspFace {
  int shader = 0;
  int type = 0;
  int first_vertex = 0, vertex_count = 0;
  int first_meshvert = 0, meshvert_count = 0;
  int lightmap = -1;             // negative for none; may lie past the lump (external lightmaps), the loader checks it
  int patch_w = 0, patch_h = 0;  // control grid of a patch (odd, >= 3)
  Vec3 normal;
};

using BspEntity = std::map<std::string, std::string>;

struct BspMap {
  std::vector<BspShaderRef> shaders;
  std::vector<BspVertex> vertices;
  std::vector<int32_t> meshverts;
  std::vector<BspFace> faces;
  int lightmap_count = 0;
  std::vector<uint8_t> lightmaps;  // lightmap_count * 128 * 128 * 3 bytes, RGB, rows in file order
  std::vector<BspEntity> entities;
  int repaired_coordinates = 0;  // non-finite texture or lightmap coordinates set to 0
};

// Parses and validates a whole BSP file held in memory.
BspMap parse_bsp(const uint8_t* data, size_t size, const std::string& name);

// Parses the entity lump's text ({ "key" "value" ... } blocks).
std::vector<BspEntity> parse_bsp_entities(const std::string& text, const std::string& name);

// Appends the triangles of a polygon, mesh or patch face (patches
// tessellated with `level` segments per 3x3 Bezier patch side) to `vertices`
// and `indices`. Triangles wind counter-clockwise seen from the front, in the
// BSP's own (z-up, right-handed) frame. Billboards produce nothing.
void bsp_face_triangles(const BspMap& map, const BspFace& face, int level, std::vector<BspVertex>& vertices,
                        std::vector<uint32_t>& indices);

constexpr int kMaxTessellation = 16;

}  // namespace oovr
