#include "oovr/scene/load.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <new>

#include "oovr/core/error.h"
#include "oovr/core/limits.h"
#include "oovr/core/out_of_memory.h"

namespace oovr {
namespace {

// Splits "name?key=value&key=value" into the name and its options.
std::string split_options(const std::string& spec, const std::string& rest_in, SceneOptions& options) {
  const auto q = rest_in.find('?');
  if (q == std::string::npos) return rest_in;
  const std::string rest = rest_in.substr(q + 1);
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
  return rest_in.substr(0, q);
}

// Sources in the order they are listed and asked: unprefixed ones by
// `order`, then prefixed ones by prefix.
std::vector<std::pair<std::string, const SceneSource*>> sources() {
  std::vector<std::pair<std::string, const SceneSource*>> out;
  for (const auto& key : SceneSources::names()) out.emplace_back(key, SceneSources::find(key));
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    if (a.second->prefixed != b.second->prefixed) return !a.second->prefixed;
    return !a.second->prefixed && a.second->order < b.second->order;
  });
  return out;
}

}  // namespace

int scene_int_option(const std::string& key, const std::string& value, const std::string& spec) {
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

void unknown_scene_option(const std::string& key, const std::string& spec, const std::string& accepted) {
  throw Error("unknown scene option '" + key + "' in '" + spec + "' (" + accepted + ")");
}

std::string scene_data_missing(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos || colon == 0) return {};
  const SceneSource* s = SceneSources::find(spec.substr(0, colon));
  if (!s || !s->prefixed || !s->data_directory) return {};
  const std::string dir = s->data_directory();
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return {};
  return s->kind + " data not installed (" + dir + "); run scripts/install-deps.sh --game-data";
}

std::vector<SceneListing> list_scenes() {
  std::vector<SceneListing> out;
  for (const auto& [key, source] : sources()) {
    if (!source->list) continue;
    for (auto& l : source->list()) out.push_back(std::move(l));
  }
  return out;
}

namespace {

Scene load_unchecked(const std::string& spec) {
  if (spec.empty()) throw Error("no scene given");
  const auto all = sources();
  if (const auto colon = spec.find(':'); colon != std::string::npos && colon > 0) {
    const SceneSource* s = SceneSources::find(spec.substr(0, colon));
    if (s && s->prefixed) {
      SceneOptions options;
      const std::string name = split_options(spec, spec.substr(colon + 1), options);
      return s->load(spec, name, options);
    }
  }
  for (const auto& [key, s] : all)
    if (!s->prefixed && s->claims && s->claims(spec)) return s->load(spec, spec, {});
  std::string forms;
  for (const auto& [key, s] : all) forms += (forms.empty() ? "" : ", ") + s->form;
  throw Error("unknown scene '" + spec + "': none of " + forms + "; 'oovr scenes' lists them");
}

}  // namespace

Scene load_scene(const std::string& spec) {
  // Every source's scene is checked in one place: whatever a loader let
  // through (a vertex at 3e38, a NaN texture coordinate) is an error here.
  Scene s;
  try {
    s = load_unchecked(spec);
  } catch (const std::bad_alloc&) {
    throw Error(out_of_memory_message("loading scene '" + spec + "'") +
                " (its files are within $OOVR_LIMITS; lower them to refuse it sooner)");
  }
  s.validate();
  // Loading was bounded file by file; the whole scene is bounded here,
  // before anything renders it.
  uint64_t bytes = 0;
  for (const auto& t : s.textures) bytes += t.bytes();
  for (const auto& m : s.meshes)
    bytes += m.vertices.size() * sizeof(Vertex) + m.indices.size() * sizeof(uint32_t) + m.frames.size() * sizeof(TangentFrame);
  check_limit(bytes, InputLimits::get().scene_bytes, "scene_bytes", "scene '" + s.name + "'", "bytes of geometry and textures");
  return s;
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

CameraPath orbit_camera_around(const Scene& s) {
  Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (const auto& o : s.objects)
    for (const auto& v : s.meshes.at(size_t(o.mesh)).vertices) {
      const Vec3 p = transform_point3(o.world_from_object, v.position);
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  return orbit_camera_path(lo, hi, 120);
}

}  // namespace oovr
