// Building blocks for the built-in procedural scenes: meshes, textures and a
// small builder. Everything is a pure function of its arguments (and seed).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "oovr/scene/scene.h"

namespace oovr::procedural {

// --- meshes (y up, counter-clockwise front faces, uv in texture repeats) ---
// Horizontal grid in the XZ plane centred on the origin, facing +Y.
Mesh grid(float size_x, float size_z, int cells_x, int cells_z, float uv_repeat_x, float uv_repeat_z);
// Vertical wall in the XY plane from x=-w/2..w/2, y=0..h, facing +Z.
Mesh wall(float width, float height, int cells_x, int cells_y, float uv_repeat_x, float uv_repeat_y);
// Box centred on the origin; uv repeats `uv_per_metre` times per metre.
Mesh box(Vec3 half, float uv_per_metre);
// Cylinder along +Y from y=0 to `height`; open ends unless `caps`.
Mesh cylinder(float radius, float height, int segments, int rings, float uv_repeat_u, float uv_repeat_v, bool caps);
// Sphere centred on the origin.
Mesh sphere(float radius, int segments, int rings, float uv_repeat_u = 1, float uv_repeat_v = 1);
// Torus in the XZ plane.
Mesh torus(float major, float minor, int segments, int sides, float uv_repeat_u = 1, float uv_repeat_v = 1);
// Upper hemisphere seen from inside (inward-facing), for a sky dome; uv.y
// runs from the horizon (0) to the zenith (1).
Mesh dome(float radius, int segments, int rings);
// Two crossed vertical quads (a billboard cluster for foliage), two-sided.
Mesh crossed_quads(float width, float height, int count, uint64_t seed);
// Appends b to a (indices rebased), with b transformed.
void append(Mesh& a, const Mesh& b, const Mat4& transform);

// --- textures (RGBA8, full mip chains) ---
using TexelFn = std::function<void(float u, float v, uint8_t* rgba)>;
Texture texture_from(const std::string& name, int size, const TexelFn& fn, Wrap wrap = Wrap::repeat, bool mipmapped = true);
// Tileable value noise in [0, 1], `period` cells per unit square.
float noise(float u, float v, int period, uint64_t seed);
// Sum of octaves of tileable noise.
float fbm(float u, float v, int period, int octaves, uint64_t seed);

Texture stone(int size, uint64_t seed);
Texture cobbles(int size, uint64_t seed);
Texture brick(int size, uint64_t seed);
Texture wood(int size, uint64_t seed);
Texture marble(int size, uint64_t seed);
Texture metal(int size, uint64_t seed);
Texture grass(int size, uint64_t seed);
Texture bark(int size, uint64_t seed);
Texture leaves(int size, uint64_t seed);  // alpha-tested foliage
Texture water(int size, uint64_t seed);
Texture sky(int size, uint64_t seed);                                     // horizon-to-zenith gradient with clouds
Texture cloth(int size, uint64_t seed, uint8_t r, uint8_t g, uint8_t b);  // banner / clothing
Texture fabric_person(int size, uint64_t seed, uint8_t r, uint8_t g, uint8_t b);

// --- a builder that hands out indices ---
class SceneBuilder {
 public:
  explicit SceneBuilder(std::string name, std::string description);
  int texture(Texture t);
  int material(Material m);
  int mesh(Mesh m);
  int object(const std::string& name, int mesh, int material, const Mat4& world_from_object);
  Scene& scene() { return m_scene; }
  Scene take();

 private:
  Scene m_scene;
};

}  // namespace oovr::procedural
