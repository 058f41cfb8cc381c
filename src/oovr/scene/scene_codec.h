// A scene as bytes and back: what caches an imported capture (a trace:
// or oa-demo: scene), so that a later run does not read the capture again.
//
// The bytes are read back as untrusted input (docs/reliability.md): every
// count is checked against the bytes left, every enumeration against its
// range, and the scene is validated (Scene::validate) before it is used;
// anything wrong is a miss with the reason, never a crash.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "oovr/scene/scene.h"

namespace oovr {

std::string encode_scene(const Scene& s);
// The scene, or nullopt with `why` set (truncated, a count past the end, a
// value out of range, a scene that does not validate).
std::optional<Scene> decode_scene(std::string_view bytes, std::string* why = nullptr);

// A cache of imported scenes in a folder ($OOVR_CACHE_DIR/imports, else
// beside the trace cache's default folder): one file per key, written
// aside and renamed into place, with a checksum.
class SceneCache {
 public:
  // `directory` empty: the default folder.
  explicit SceneCache(std::string directory = "");
  const std::string& directory() const { return m_dir; }
  // The scene stored under `key`, or nullopt (a miss; `why` says why when a
  // file was there but could not be used).
  std::optional<Scene> load(const std::string& key, std::string* why = nullptr) const;
  // Stores `s` under `key`; a failure to write is not an error (the next
  // run imports again).
  void store(const std::string& key, const Scene& s) const;

 private:
  std::string path(const std::string& key) const;
  std::string m_dir;
};

}  // namespace oovr
