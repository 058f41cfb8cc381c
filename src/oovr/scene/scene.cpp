#include "oovr/scene/scene.h"

#include "oovr/core/error.h"

namespace oovr {

uint64_t Scene::triangle_count() const {
  uint64_t n = 0;
  for (const auto& o : objects) n += meshes[size_t(o.mesh)].triangle_count();
  return n;
}

uint64_t Scene::vertex_count() const {
  uint64_t n = 0;
  for (const auto& o : objects) n += meshes[size_t(o.mesh)].vertices.size();
  return n;
}

uint64_t Scene::texture_bytes() const {
  uint64_t n = 0;
  for (const auto& t : textures) n += t.bytes();
  return n;
}

std::vector<int> Scene::textures_of(const Object& o) const {
  std::vector<int> t;
  const Material& m = materials[size_t(o.material)];
  if (m.diffuse >= 0) t.push_back(m.diffuse);
  if (m.lightmap >= 0) t.push_back(m.lightmap);
  return t;
}

void Scene::validate() const {
  const auto where = [&](const std::string& what) { return "scene '" + name + "': " + what; };
  for (size_t i = 0; i < textures.size(); ++i) {
    const Texture& t = textures[i];
    if (t.levels.empty() || t.width() <= 0 || t.height() <= 0)
      throw Error(where("texture '" + t.name + "' has no image"));
    for (const auto& l : t.levels)
      if (l.rgba.size() != size_t(l.width) * l.height * 4)
        throw Error(where("texture '" + t.name + "' has a level of the wrong size"));
  }
  for (const auto& m : materials) {
    if (m.diffuse >= int(textures.size()) || m.lightmap >= int(textures.size()))
      throw Error(where("material '" + m.name + "' names a texture that does not exist"));
  }
  for (const auto& mesh : meshes) {
    if (mesh.indices.size() % 3 != 0)
      throw Error(where("mesh '" + mesh.name + "' has an index count that is not a multiple of 3"));
    for (uint32_t i : mesh.indices)
      if (i >= mesh.vertices.size())
        throw Error(where("mesh '" + mesh.name + "' has an index past its vertices"));
  }
  for (size_t k = 0; k < objects.size(); ++k) {
    const Object& o = objects[k];
    if (o.mesh < 0 || o.mesh >= int(meshes.size()))
      throw Error(where("object '" + o.name + "' names a mesh that does not exist"));
    if (o.material < 0 || o.material >= int(materials.size()))
      throw Error(where("object '" + o.name + "' names a material that does not exist"));
    for (uint32_t p : o.after)
      if (p >= k) throw Error(where("object '" + o.name + "' must follow a draw that is not before it"));
  }
  if (camera.frames.empty()) throw Error(where("camera path has no frames"));
}

}  // namespace oovr
