#include "oovr/scene/scene.h"

#include <algorithm>
#include <cmath>

#include "oovr/core/error.h"
#include "oovr/core/limits.h"
#include "oovr/core/units.h"

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
  for (const TextureLayer& l : pass_of(o).layers)
    if (l.texture >= 0 && std::find(t.begin(), t.end(), l.texture) == t.end()) t.push_back(l.texture);
  return t;
}

uint32_t Scene::add_draws(const std::string& object_name, int mesh, int material, const Mat4& world_from_object,
                          std::vector<uint32_t> after) {
  const uint32_t first = uint32_t(objects.size());
  const size_t passes = materials.at(size_t(material)).passes.size();
  for (size_t p = 0; p < passes; ++p) {
    Object o;
    o.name = passes > 1 ? object_name + " pass " + std::to_string(p) : object_name;
    o.mesh = mesh;
    o.material = material;
    o.pass = int(p);
    o.world_from_object = world_from_object;
    // A later pass blends over the earlier ones: it must follow them
    // (OO-VR's middleware keeps them in one batch, Section 5.1).
    o.after = p == 0 ? after : std::vector<uint32_t>{uint32_t(objects.size()) - 1};
    objects.push_back(std::move(o));
  }
  return first;
}

void Scene::validate() const {
  const auto where = [&](const std::string& what) { return "scene '" + name + "': " + what; };
  // Every source's scene, before the simulator spends ~18 KB on each draw.
  check_limit(objects.size(), InputLimits::get().draws, "draws", "scene '" + name + "'", "draws");
  for (size_t i = 0; i < textures.size(); ++i) {
    const Texture& t = textures[i];
    if (t.levels.empty() || t.width() <= 0 || t.height() <= 0) throw Error(where("texture '" + t.name + "' has no image"));
    for (const auto& l : t.levels)
      if (l.rgba.size() != size_t(l.width) * l.height * 4)
        throw Error(where("texture '" + t.name + "' has a level of the wrong size"));
  }
  for (const auto& m : materials) {
    if (m.passes.empty()) throw Error(where("material '" + m.name + "' has no pass"));
    for (const Pass& p : m.passes) {
      for (const TextureLayer& l : p.layers)
        if (l.texture < 0 || l.texture >= int(textures.size()))
          throw Error(where("material '" + m.name + "' has a " + layer_kind_name(l.kind) +
                            " layer naming a texture that does not exist"));
      if (p.shading == Shading::deluxe &&
          (p.layer(LayerKind::diffuse) < 0 || p.layer(LayerKind::lightmap) < 0 || p.layer(LayerKind::deluxe) < 0))
        throw Error(where("material '" + m.name + "' has a deluxe-lit pass without diffuse, lightmap and deluxe layers"));
    }
  }
  for (const auto& mesh : meshes) {
    if (mesh.indices.size() % 3 != 0)
      throw Error(where("mesh '" + mesh.name + "' has an index count that is not a multiple of 3"));
    for (uint32_t i : mesh.indices)
      if (i >= mesh.vertices.size()) throw Error(where("mesh '" + mesh.name + "' has an index past its vertices"));
    if (!mesh.frames.empty() && mesh.frames.size() != mesh.vertices.size())
      throw Error(where("mesh '" + mesh.name + "' has tangent frames for some vertices only"));
    // Positions far enough out to overflow a float once transformed (a
    // vertex at 3e38 blanked a model while the timing model reported it as
    // nearly free) or not numbers at all are refused; texture coordinates
    // must be numbers (the sampler converts them to texel indices).
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
      const Vertex& x = mesh.vertices[v];
      for (const float c : {x.position.x, x.position.y, x.position.z})
        if (!(std::fabs(c) <= kMaxCoordinate))
          throw Error(where("mesh '" + mesh.name + "' has vertex " + std::to_string(v) + " at a coordinate of " +
                            format_number(c) + ", beyond 1e9 units or not a number"));
      for (const float c : {x.uv.x, x.uv.y, x.lm_uv.x, x.lm_uv.y})
        if (!std::isfinite(c))
          throw Error(where("mesh '" + mesh.name + "' has vertex " + std::to_string(v) +
                            " with a texture coordinate that is not a number"));
    }
  }
  for (size_t k = 0; k < objects.size(); ++k) {
    const Object& o = objects[k];
    if (o.mesh < 0 || o.mesh >= int(meshes.size()))
      throw Error(where("object '" + o.name + "' names a mesh that does not exist"));
    if (o.material < 0 || o.material >= int(materials.size()))
      throw Error(where("object '" + o.name + "' names a material that does not exist"));
    if (o.pass < 0 || o.pass >= int(materials[size_t(o.material)].passes.size()))
      throw Error(where("object '" + o.name + "' draws a pass its material does not have"));
    for (uint32_t p : o.after)
      if (p >= k) throw Error(where("object '" + o.name + "' must follow a draw that is not before it"));
    if (pass_of(o).shading == Shading::deluxe && meshes[size_t(o.mesh)].frames.empty())
      throw Error(where("object '" + o.name + "' is lit per pixel but its mesh has no tangent frames"));
  }
  if (camera.frames.empty()) throw Error(where("camera path has no frames"));
}

}  // namespace oovr
