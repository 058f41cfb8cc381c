#include "oovr/scene/scene_info.h"

#include <algorithm>
#include <set>

namespace oovr {

SceneInfo scene_info(const Scene& s) {
  SceneInfo i;
  i.name = s.name;
  // A captured game's figures are its first frame's, with the spread of
  // draws over its frames beside them.
  const std::vector<Object>& draws = s.draws(0);
  i.draws = draws.size();
  i.triangles = s.triangle_count();
  i.vertices = s.vertex_count();
  if (s.captured()) {
    std::vector<uint64_t> n;
    for (const auto& f : s.frame_objects) n.push_back(f.size());
    std::sort(n.begin(), n.end());
    i.draws_min = n.front();
    i.draws_median = n[n.size() / 2];
    i.draws_max = n.back();
  }
  i.meshes = s.meshes.size();
  i.materials = s.materials.size();
  i.textures = s.textures.size();
  i.texture_bytes = s.texture_bytes();
  i.camera_frames = s.camera.frames.size();
  for (const auto& t : s.textures) i.texture_use.push_back({t.name, t.width(), t.height(), int(t.levels.size()), t.bytes(), 0});
  for (const auto& o : draws) {
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

nlohmann::ordered_json scene_info_json(const SceneInfo& i, const std::vector<std::string>& notes) {
  nlohmann::ordered_json j;
  j["scene"] = i.name;
  j["draws"] = i.draws;
  j["triangles"] = i.triangles;
  j["vertices"] = i.vertices;
  j["meshes"] = i.meshes;
  j["materials"] = i.materials;
  j["textures"] = i.textures;
  j["texture_bytes"] = i.texture_bytes;
  j["camera_frames"] = i.camera_frames;
  if (i.draws_max) j["draws_per_frame"] = {{"min", i.draws_min}, {"median", i.draws_median}, {"max", i.draws_max}};
  j["texture_layers"] = i.texture_layers;
  j["lit_draws"] = i.lit_draws;
  j["max_objects_sharing_a_texture"] = i.max_sharing;
  nlohmann::ordered_json hist = nlohmann::ordered_json::object();
  for (const auto& [objects, textures] : i.sharing_histogram) hist[std::to_string(objects)] = textures;
  j["sharing_histogram"] = hist;
  nlohmann::ordered_json tex = nlohmann::ordered_json::array();
  for (const auto& t : i.texture_use)
    tex.push_back({{"name", t.name},
                   {"width", t.width},
                   {"height", t.height},
                   {"levels", t.levels},
                   {"bytes", t.bytes},
                   {"objects", t.objects}});
  j["texture_list"] = tex;
  j["notes"] = notes;
  return j;
}

}  // namespace oovr
