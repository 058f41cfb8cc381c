#include "oovr/scene/scene_info.h"

#include <algorithm>
#include <set>

namespace oovr {

SceneInfo scene_info(const Scene& s) {
  SceneInfo i;
  i.name = s.name;
  i.draws = s.objects.size();
  i.triangles = s.triangle_count();
  i.vertices = s.vertex_count();
  i.meshes = s.meshes.size();
  i.materials = s.materials.size();
  i.textures = s.textures.size();
  i.texture_bytes = s.texture_bytes();
  i.camera_frames = s.camera.frames.size();
  for (const auto& t : s.textures) i.texture_use.push_back({t.name, t.width(), t.height(), int(t.levels.size()), t.bytes(), 0});
  for (const auto& o : s.objects) {
    i.texture_layers += s.pass_of(o).layers.size();
    i.lit_draws += s.pass_of(o).shading == Shading::deluxe;
    // An object counts once per texture even if it names it twice.
    const auto tex = s.textures_of(o);
    for (int t : std::set<int>(tex.begin(), tex.end())) ++i.texture_use[size_t(t)].objects;
  }
  for (const auto& u : i.texture_use) {
    ++i.sharing_histogram[u.objects];
    i.max_sharing = std::max(i.max_sharing, u.objects);
  }
  return i;
}

}  // namespace oovr
