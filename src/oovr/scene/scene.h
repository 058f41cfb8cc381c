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
  // One RGBA8 colour per vertex (red in the low byte), multiplying the
  // pass's colour as OpenGL's primary colour does (a captured game's
  // glColorPointer, glColor); empty: white.
  std::vector<uint32_t> colours;

  uint64_t triangle_count() const { return indices.size() / 3; }
  // Bytes of the vertex buffer: positions, coordinates, any frames and colours.
  uint64_t vertex_bytes() const {
    return vertices.size() * sizeof(Vertex) + frames.size() * sizeof(TangentFrame) + colours.size() * sizeof(uint32_t);
  }
};

// How a draw is placed in each eye's view.
//  - world: world_from_object places it; each eye views the world from the
//    camera path (levels and models).
//  - captured: a 3-D draw of a captured mono game (trace: scenes).
//    world_from_object is the game camera's eye_from_object (its modelview,
//    scaled to metres) and clip_from_eye the draw's own projection; each eye
//    re-projects it from its offset from the head, as the paper made stereo
//    from mono traces in ATTILA (Section 6): clip = clip_from_eye x
//    eye_from_head x world_from_object.
//  - screen: a 2-D draw of a captured game (an orthographic projection: HUD,
//    menus, console), drawn alike in both eyes: clip = clip_from_eye x
//    world_from_object.
enum class DrawView : uint8_t { world, captured, screen };
const char* draw_view_name(DrawView v);

// A rectangle of an eye's viewport, as fractions of its width and height
// from its bottom-left corner (OpenGL's window convention).
struct ViewRect {
  float x0 = 0, y0 = 0, x1 = 1, y1 = 1;
  bool whole() const { return x0 <= 0 && y0 <= 0 && x1 >= 1 && y1 >= 1; }
  bool operator==(const ViewRect&) const = default;
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
  DrawView view = DrawView::world;
  Mat4 clip_from_eye;  // captured and screen draws: the draw's projection
  // Pixels outside this part of each eye's viewport are not drawn (a
  // captured game's glScissor, and a glViewport smaller than its window).
  ViewRect scissor;

  // A world draw of pass 0.
  static Object of(std::string name, int mesh, int material, const Mat4& world_from_object) {
    Object o;
    o.name = std::move(name);
    o.mesh = mesh;
    o.material = material;
    o.world_from_object = world_from_object;
    return o;
  }
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
  std::vector<Object> objects;  // draw order, the same in every frame
  // A captured game draws different objects in each frame: frame f of the
  // camera path then draws frame_objects[f] (in draw order) instead of
  // `objects`, which stays empty. Meshes, materials and textures are shared
  // by every frame.
  std::vector<std::vector<Object>> frame_objects;
  CameraPath camera;
  // Metres per scene unit: 1 for every loader that converts to metres; a
  // captured game keeps its own units (Quake's inch: 0.0254), and the
  // stereo rig's eye offsets are divided by it.
  float metres_per_unit = 1.0f;
  // A captured game: frame k of the camera path is the game's frame
  // capture_first_frame + k, drawn into a capture_width x capture_height
  // window (0 for other scenes).
  int capture_first_frame = 0, capture_width = 0, capture_height = 0;
  // What a loader left out or replaced (skipped surfaces, missing images),
  // one line each; `oovr scene-info` prints them.
  std::vector<std::string> notes;

  // The draws of camera frame `frame`, in order.
  const std::vector<Object>& draws(int frame) const {
    return frame_objects.empty() ? objects : frame_objects[size_t(frame) % frame_objects.size()];
  }
  bool captured() const { return !frame_objects.empty(); }

  // Triangles and vertices of frame `frame`'s draws.
  uint64_t triangle_count(int frame = 0) const;
  uint64_t vertex_count(int frame = 0) const;
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

 private:
  void check_object(const std::vector<Object>& draws, size_t k) const;
};

}  // namespace oovr
