// Finding scenes by name: built-in procedural scenes and model files.
#pragma once

#include <string>
#include <vector>

#include "oovr/scene/scene.h"

namespace oovr {

struct SceneListing {
  std::string name;
  std::string kind;  // "built-in", later "openarena", "torcs"
  std::string description;
};

// Every scene `load_scene` accepts by name.
std::vector<SceneListing> list_scenes();

// A built-in scene name or a path to a model file (OBJ, glTF, PLY, AC3D).
// Throws Error saying what is wrong (unknown name, missing or bad file).
Scene load_scene(const std::string& spec);

// Loads a model file through assimp.
Scene load_model_file(const std::string& path);

// A path of `frames` poses circling the box [lo, hi], looking at its centre
// from a little above; near and far planes sized to the box.
CameraPath orbit_camera_path(Vec3 lo, Vec3 hi, int frames);

}  // namespace oovr
