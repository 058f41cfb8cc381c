#include "oovr/scene/scene.h"

#include <algorithm>
#include <cmath>

#include "oovr/core/error.h"
#include "oovr/core/limits.h"
#include "oovr/core/units.h"

namespace oovr {

const char* draw_view_name(DrawView v) {
  switch (v) {
    case DrawView::world: return "world";
    case DrawView::captured: return "captured";
    case DrawView::screen: return "screen";
  }
  return "?";
}

uint64_t Scene::triangle_count(int frame) const {
  uint64_t n = 0;
  for (const auto& o : draws(frame)) n += meshes[size_t(o.mesh)].triangle_count();
  return n;
}

uint64_t Scene::vertex_count(int frame) const {
  uint64_t n = 0;
  for (const auto& o : draws(frame)) n += meshes[size_t(o.mesh)].vertices.size();
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
  if (!frame_objects.empty()) {
    if (!objects.empty()) throw Error(where("has both draws for every frame and draws per frame"));
    if (frame_objects.size() != camera.frames.size())
      throw Error(where("has draws for " + std::to_string(frame_objects.size()) + " frames and a camera path of " +
                        std::to_string(camera.frames.size())));
    for (const auto& f : frame_objects)
      check_limit(f.size(), InputLimits::get().draws, "draws", "scene '" + name + "'", "draws in a frame");
  }
  for (size_t i = 0; i < textures.size(); ++i) {
    const Texture& t = textures[i];
    if (t.levels.empty() || t.width() <= 0 || t.height() <= 0) throw Error(where("texture '" + t.name + "' has no image"));
    if (t.width() > InputLimits::get().image_side || t.height() > InputLimits::get().image_side)
      throw Error(where("texture '" + t.name + "' is larger than the image_side limit"));
    // Level k is max(1, base >> k) on each side, as OpenGL's chains (and
    // every loader's) are: the sampler relies on it.
    for (size_t k = 0; k < t.levels.size(); ++k) {
      const MipLevel& l = t.levels[k];
      const int w = k < 31 ? std::max(1, t.width() >> k) : 1, h = k < 31 ? std::max(1, t.height() >> k) : 1;
      if (l.width != w || l.height != h || (k > 0 && t.levels[k - 1].width == 1 && t.levels[k - 1].height == 1))
        throw Error(where("texture '" + t.name + "' has a mip level of the wrong size"));
      if (l.rgba.size() != size_t(l.width) * size_t(l.height) * 4)
        throw Error(where("texture '" + t.name + "' has a level of the wrong size"));
    }
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
    if (!mesh.colours.empty() && mesh.colours.size() != mesh.vertices.size())
      throw Error(where("mesh '" + mesh.name + "' has colours for some vertices only"));
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
  for (int f = 0; f < std::max<int>(1, int(frame_objects.size())); ++f) {
    const std::vector<Object>& list = draws(f);
    for (size_t k = 0; k < list.size(); ++k) check_object(list, k);
  }
  if (camera.frames.empty()) throw Error(where("camera path has no frames"));
}

void Scene::check_object(const std::vector<Object>& list, size_t k) const {
  const auto where = [&](const std::string& what) { return "scene '" + name + "': " + what; };
  {
    const Object& o = list[k];
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
    if (o.view != DrawView::world && pass_of(o).shading == Shading::deluxe)
      throw Error(where("object '" + o.name + "' is a captured draw lit per pixel, which oovr does not draw"));
    const ViewRect& r = o.scissor;
    if (!(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= 1 && r.y1 <= 1 && r.x0 <= r.x1 && r.y0 <= r.y1))
      throw Error(where("object '" + o.name + "' has a scissor rectangle outside its viewport"));
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row)
        if (!std::isfinite(o.clip_from_eye.at(row, c)) || !std::isfinite(o.world_from_object.at(row, c)))
          throw Error(where("object '" + o.name + "' has a transform that is not finite"));
  }
}

}  // namespace oovr
