#include "oovr/framework/oo_application.h"

#include <algorithm>

#include "oovr/core/error.h"

namespace oovr {
namespace {

uint64_t texture_bytes(const Texture& t) {
  uint64_t b = 0;
  for (const auto& l : t.levels) b += uint64_t(l.width) * uint64_t(l.height) * 4;
  return b;
}

}  // namespace

uint32_t OOApplication::add_object(const Scene& scene, uint32_t draw, Viewport left, Viewport right, int frame) {
  const std::vector<Object>& draws = scene.draws(frame);
  if (draw >= draws.size()) throw Error("OO application: draw " + std::to_string(draw) + " does not exist");
  const Object& so = draws[draw];
  const Mesh& mesh = scene.meshes[size_t(so.mesh)];
  OOObject o;
  o.draw = draw;
  o.viewport[0] = left;
  o.viewport[1] = right;
  o.triangles = mesh.indices.size() / 3;
  o.vertices = mesh.vertices.size();
  for (int t : scene.textures_of(so)) o.textures.push_back({uint32_t(t), texture_bytes(scene.textures[size_t(t)])});
  m_objects.push_back(std::move(o));
  return uint32_t(m_objects.size() - 1);
}

uint32_t OOApplication::add_object_auto(const Scene& scene, uint32_t draw, Viewport viewport, int frame) {
  Viewport right = viewport;
  right.x += viewport.width;
  return add_object(scene, draw, viewport, right, frame);
}

void OOApplication::add_dependency(uint32_t object, uint32_t earlier) {
  if (object >= m_objects.size() || earlier >= object)
    throw Error("OO application: object " + std::to_string(object) + " can only follow an object added before it");
  auto& a = m_objects[object].after;
  if (std::find(a.begin(), a.end(), earlier) == a.end()) a.push_back(earlier);
}

OOApplication make_application(const Scene& scene, int frame_width, int frame_height, int frame) {
  OOApplication app;
  const Viewport left{0, 0, frame_width / 2, frame_height};
  // Draws and objects correspond one to one, so a draw's constraints name
  // objects with the same indices.
  const std::vector<Object>& draws = scene.draws(frame);
  for (uint32_t d = 0; d < draws.size(); ++d) {
    app.add_object_auto(scene, d, left, frame);
    for (uint32_t p : draws[d].after) app.add_dependency(d, p);
  }
  return app;
}

}  // namespace oovr
