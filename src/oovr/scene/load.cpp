#include "oovr/scene/load.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "oovr/core/error.h"
#include "oovr/scene/builtin.h"
#include "oovr/scene/openarena.h"
#include "oovr/scene/torcs.h"

namespace oovr {
namespace {

// Splits "name?key=value&key=value" into the name and its options.
std::string split_options(const std::string& spec, std::map<std::string, std::string>& options) {
  const auto q = spec.find('?');
  if (q == std::string::npos) return spec;
  std::string rest = spec.substr(q + 1);
  size_t i = 0;
  while (i <= rest.size()) {
    const size_t amp = std::min(rest.find('&', i), rest.size());
    const std::string kv = rest.substr(i, amp - i);
    const auto eq = kv.find('=');
    if (kv.empty() || eq == std::string::npos || eq == 0)
      throw Error("bad scene option '" + kv + "' in '" + spec + "': expected key=value");
    options[kv.substr(0, eq)] = kv.substr(eq + 1);
    i = amp + 1;
  }
  return spec.substr(0, q);
}

int parse_int_option(const std::string& key, const std::string& value, const std::string& spec) {
  size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || value.empty())
    throw Error("scene option '" + key + "' in '" + spec + "' must be a whole number, not '" + value + "'");
  return v;
}

Scene load_openarena(const std::string& spec, const std::string& map, const std::map<std::string, std::string>& options) {
  OpenArenaOptions o;
  for (const auto& [k, v] : options) {
    if (k == "group") {
      if (v == "shader-lightmap") o.group = OpenArenaOptions::Group::shader_lightmap;
      else if (v == "face") o.group = OpenArenaOptions::Group::face;
      else throw Error("scene option group='" + v + "' in '" + spec + "': expected shader-lightmap or face");
    } else if (k == "tess") {
      o.tessellation = parse_int_option(k, v, spec);
    } else {
      throw Error("unknown scene option '" + k + "' in '" + spec + "' (OpenArena maps take group and tess)");
    }
  }
  return load_openarena_map(map, o);
}

}  // namespace

std::vector<SceneListing> list_scenes() {
  std::vector<SceneListing> out;
  for (const auto& name : BuiltinScenes::names())
    out.push_back({name, "built-in", BuiltinScenes::find(name)->description});
  for (const auto& map : list_openarena_maps()) out.push_back({"oa:" + map, "openarena", "OpenArena map"});
  for (const auto& t : list_torcs_tracks()) out.push_back({"torcs:" + t.name, "torcs", "TORCS " + t.category + " track"});
  return out;
}

Scene load_scene(const std::string& spec) {
  if (spec.empty()) throw Error("no scene given");
  if (const BuiltinScene* b = BuiltinScenes::find(spec)) return b->make();
  std::map<std::string, std::string> options;
  if (spec.rfind("oa:", 0) == 0) {
    const std::string map = split_options(spec.substr(3), options);
    return load_openarena(spec, map, options);
  }
  if (spec.rfind("torcs:", 0) == 0) {
    const std::string track = split_options(spec.substr(6), options);
    if (!options.empty()) throw Error("unknown scene option '" + options.begin()->first + "' in '" + spec + "' (TORCS tracks take none)");
    return load_torcs_track(track);
  }
  std::error_code ec;
  if (std::filesystem::exists(spec, ec)) return load_model_file(spec);
  std::string names;
  for (const auto& n : BuiltinScenes::names()) names += (names.empty() ? "" : ", ") + n;
  throw Error("unknown scene '" + spec + "': not a built-in scene (" + names +
              "), not oa:MAP or torcs:TRACK, and no such file; 'oovr scenes' lists them");
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
