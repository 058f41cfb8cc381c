// The scene model: what every loader produces and every later stage reads.
//
// An Object is one draw call (the paper's unit of work; Section 3, Table 2 counts draw commands): a mesh,
// a transform and a material (texture set), issued in the order of
// Scene::objects. Textures are shared by index, never copied, so texture
// sharing between objects (the basis of OO-VR's batching, Section 5.1) is
// visible in the model: many materials may name the same texture.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/core/math.h"
#include "oovr/scene/material.h"
#include "oovr/scene/texture.h"

namespace oovr {

// The largest vertex coordinate a scene may hold (Scene::validate): far
// beyond any level or model (game maps reach 10^5 units), far below what
// overflows a float once transformed.
constexpr float kMaxCoordinate = 1e9f;

struct Vertex {
  Vec3 position;
  Vec2 uv;     // diffuse texture coordinates
  Vec2 lm_uv;  // lightmap coordinates (unused when the material has no lightmap)
};

// A vertex's tangent frame, for per-pixel lighting (Shading::deluxe): S
// and T follow the surface texture's s and t directions, N is the surface
// normal; world space, unit length, S and T perpendicular to N (DarkPlaces'
// svector, tvector and normal).
struct TangentFrame {
  Vec3 s, t, n;
};

struct Mesh {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // triangle list
  // One per vertex when the mesh is drawn with per-pixel lighting, else
  // empty; the vertex buffer then holds both (vertex_bytes).
  std::vector<TangentFrame> frames;

  uint64_t triangle_count() const { return indices.size() / 3; }
  // Bytes of the vertex buffer: positions, coordinates and any frames.
  uint64_t vertex_bytes() const { return vertices.size() * sizeof(Vertex) + frames.size() * sizeof(TangentFrame); }
};

struct Object {
  std::string name;
  int mesh = 0;
  int material = 0;
  Mat4 world_from_object;
  // Earlier draws this one must follow (an application's ordering
  // constraint, e.g. a decal after its wall, a blended surface after what is
  // behind it). Indices are smaller than this object's own. Rendering ignores
  // them (draw order already respects them); OO-VR's middleware keeps such
  // objects in one batch, in this order (paper Section 5.1).
  std::vector<uint32_t> after = {};
  int pass = 0;  // which of the material's passes this draw draws
};

// One camera pose of a path: the head (centre between the eyes).
struct CameraPose {
  Vec3 position;
  Vec3 target;
  Vec3 up{0, 1, 0};
};

struct CameraPath {
  std::vector<CameraPose> frames;
  float fov_y_degrees = 90.0f;  // vertical field of view of each eye
  float z_near = 0.05f;
  float z_far = 500.0f;
  // Frames per second of the path: frame f is shown at f / rate seconds
  // (animated texture coordinates use it).
  float frames_per_second = 60.0f;

  double seconds(int frame) const { return double(frame) / double(frames_per_second); }
};

struct Scene {
  std::string name;
  std::string description;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Object> objects;  // draw order
  CameraPath camera;
  // What a loader left out or replaced (skipped surfaces, missing images),
  // one line each; `oovr scene-info` prints them.
  std::vector<std::string> notes;

  uint64_t triangle_count() const;
  uint64_t vertex_count() const;
  uint64_t texture_bytes() const;
  // Texture indices an object's pass samples, in layer order, each once.
  std::vector<int> textures_of(const Object& o) const;
  const Pass& pass_of(const Object& o) const { return materials[size_t(o.material)].passes[size_t(o.pass)]; }
  // Appends one object per pass of `material` (drawn in pass order, each
  // after the one before) and returns the first one's index.
  uint32_t add_draws(const std::string& object_name, int mesh, int material, const Mat4& world_from_object,
                     std::vector<uint32_t> after = {});
  // Throws Error when an index is out of range or a mesh is malformed, so a
  // loader bug or a bad file cannot crash the pipeline later.
  void validate() const;
};

}  // namespace oovr
