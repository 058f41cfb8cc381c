#include "oovr/scene/load.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "oovr/core/error.h"
#include "oovr/scene/builtin.h"

namespace oovr {

std::vector<SceneListing> list_scenes() {
  std::vector<SceneListing> out;
  for (const auto& name : BuiltinScenes::names())
    out.push_back({name, "built-in", BuiltinScenes::find(name)->description});
  return out;
}

Scene load_scene(const std::string& spec) {
  if (spec.empty()) throw Error("no scene given");
  if (const BuiltinScene* b = BuiltinScenes::find(spec)) return b->make();
  std::error_code ec;
  if (std::filesystem::exists(spec, ec)) return load_model_file(spec);
  std::string names;
  for (const auto& n : BuiltinScenes::names()) names += (names.empty() ? "" : ", ") + n;
  throw Error("unknown scene '" + spec + "': not a built-in scene (" + names +
              ") and no such file; 'oovr scenes' lists them");
}

CameraPath orbit_camera_path(Vec3 lo, Vec3 hi, int frames) {
  const Vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(length(hi - lo) * 0.5f, 1e-3f);
  CameraPath path;
  path.fov_y_degrees = 60.0f;
  path.z_near = radius * 0.01f;
  path.z_far = radius * 8.0f;
  for (int f = 0; f < frames; ++f) {
    const float a = 2 * kPi * float(f) / float(frames) + 0.6f;
    CameraPose pose;
    pose.position = centre + Vec3{2.2f * radius * std::sin(a), 0.6f * radius, 2.2f * radius * std::cos(a)};
    pose.target = centre;
    path.frames.push_back(pose);
  }
  return path;
}

}  // namespace oovr
