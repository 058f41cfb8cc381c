// Helpers shared by the tests: exact orthographic views and tiny scenes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "oovr/core/error.h"

#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/builtin.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr::test {

// The message of the Error `f` throws, or "<no error>".
inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

// The names registered in the sources of `folder` (relative to the source
// tree, every .cpp in it) with `Registry::Add name("NAME", ...)`: what the
// registry must hold if every file there is compiled and linked, found
// without a hand-kept list, so that a new file alone passes its test.
inline std::vector<std::string> registered_in_sources(const std::string& folder, const std::string& registry) {
  std::vector<std::string> names;
  const std::regex add(registry + R"re(::Add\s+\w+\(\s*"([^"]+)")re");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(OOVR_SOURCE_DIR) / folder)) {
    if (e.path().extension() != ".cpp") continue;
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string t = text.str();
    for (auto it = std::sregex_iterator(t.begin(), t.end(), add); it != std::sregex_iterator(); ++it) names.push_back((*it)[1]);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Consecutive frames of a built-in scene, rendered for scheme tests: the
// scene, the frames' outputs and their traces (which point into `out`).
struct RenderedFrames {
  Scene scene;
  std::vector<FrameOutput> out;
  std::vector<const FrameTrace*> traces;
};
// Frames first .. first + count - 1 of the built-in scene `name`, each eye
// eye_width x eye_height.
inline std::unique_ptr<RenderedFrames> render_builtin(const std::string& name, int eye_width, int eye_height, int first,
                                                      int count, const PipelineSettings& settings = {}) {
  auto r = std::make_unique<RenderedFrames>(RenderedFrames{BuiltinScenes::find(name)->make(), {}, {}});
  StereoRig rig;
  rig.eye_width = eye_width;
  rig.eye_height = eye_height;
  for (int f = first; f < first + count; ++f)
    r->out.push_back(render_frame(r->scene, make_stereo_view(r->scene.camera, f, rig), settings, f));
  for (const auto& o : r->out) r->traces.push_back(&o.trace);
  return r;
}

// A one-eye view of a w x h frame (powers of two) in which world (x, y)
// lands exactly on window (x, y) and world z in [-1, 1] is the depth.
inline StereoView ortho_view(int w, int h) {
  StereoView v;
  v.eyes = 1;
  v.frame_width = w;
  v.frame_height = h;
  v.viewport[0] = {0, 0, w, h};
  Mat4 m;
  m.at(0, 0) = 2.0f / float(w);
  m.at(0, 3) = -1.0f;
  m.at(1, 1) = 2.0f / float(h);
  m.at(1, 3) = -1.0f;
  v.clip_from_world[0] = m;
  return v;
}

// A scene holding one untextured white object made of the given triangles
// (world-space xy, z = 0), two-sided, plus a one-frame camera path.
inline Scene triangle_scene(const std::vector<Vec2>& points, const std::vector<uint32_t>& indices) {
  Scene s;
  s.name = "triangles";
  Mesh m;
  for (const auto& p : points) {
    Vertex v;
    v.position = {p.x, p.y, 0.0f};
    m.vertices.push_back(v);
  }
  m.indices = indices;
  s.meshes.push_back(m);
  Material mat = Material::textured("white", -1);
  mat.two_sided = true;
  s.materials.push_back(mat);
  s.objects.push_back(Object::of("triangles", 0, 0, Mat4::identity()));
  s.camera.frames.push_back({});
  return s;
}

inline PipelineSettings exact_settings(unsigned threads = 1) {
  PipelineSettings p;
  p.max_anisotropy = 1;
  p.threads = threads;
  return p;
}

}  // namespace oovr::test
