// Summary numbers of a scene, as `oovr scene-info` prints them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oovr/scene/scene.h"

namespace oovr {

struct TextureUse {
  std::string name;
  int width = 0, height = 0, levels = 0;
  uint64_t bytes = 0;  // all mip levels
  int objects = 0;     // draws that sample it
};

struct SceneInfo {
  std::string name;
  uint64_t draws = 0, triangles = 0, vertices = 0, meshes = 0, materials = 0;
  uint64_t textures = 0, texture_bytes = 0;
  uint64_t camera_frames = 0;
  // A captured game's draws per frame (0 for scenes that draw the same in
  // every frame); the other figures are its first frame's.
  uint64_t draws_min = 0, draws_median = 0, draws_max = 0;
  uint64_t texture_layers = 0;          // layers sampled, summed over the draws (passes)
  uint64_t lit_draws = 0;               // draws lit per pixel (Shading::deluxe)
  std::vector<TextureUse> texture_use;  // in texture order
  // objects-per-texture -> number of textures shared by that many objects
  std::map<int, int> sharing_histogram;
  int max_sharing = 0;  // most objects sharing one texture
};

SceneInfo scene_info(const Scene& s);

// `oovr scene-info --json`: the figures above with the loader's notes.
nlohmann::ordered_json scene_info_json(const SceneInfo& i, const std::vector<std::string>& notes);

}  // namespace oovr
