// A disk cache of FrameTraces (render once, replay per scheme): a trace is
// stored under a key made from everything that decides it: the scene's
// content (a hash of its geometry, textures, objects and camera), the frame,
// the stereo view, and the pipeline settings. A stale or corrupt entry is a
// miss, never a wrong answer; the key includes a hash of the executable, so a
// rebuilt oovr never replays traces made by older code.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "oovr/pipeline/frame_trace.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

// A hash of everything in the scene that a render depends on.
uint64_t scene_fingerprint(const Scene& s);

class TraceCache {
 public:
  // `directory` empty: $OOVR_CACHE_DIR, else $XDG_CACHE_HOME/oovr/traces,
  // else ~/.cache/oovr/traces. The cache holds at most $OOVR_CACHE_MAX_MB
  // megabytes (default 2048): storing a trace drops the least recently used
  // others until it fits.
  explicit TraceCache(std::string directory = {});
  const std::string& directory() const { return m_dir; }
  uint64_t max_bytes() const { return m_max_bytes; }
  void set_max_bytes(uint64_t b) { m_max_bytes = b; }

  std::string key(uint64_t scene_fingerprint, int frame, const StereoView& view, const PipelineSettings& s) const;
  std::optional<FrameTrace> load(const std::string& key) const;
  // Best effort: a cache that cannot be written is skipped, not an error.
  bool store(const std::string& key, const FrameTrace& t) const;

 private:
  void trim(const std::filesystem::path& keep) const;

  std::string m_dir;
  uint64_t m_max_bytes = uint64_t(2048) << 20;
};

// Writes / reads the binary form of a trace (also used by the tests).
std::string serialize_trace(const FrameTrace& t);
std::optional<FrameTrace> deserialize_trace(const std::string& bytes);

}  // namespace oovr
