// A disk cache of FrameTraces (render once, replay per scheme): a trace is
// stored under a key made from everything that decides it: the scene's
// content (a hash of its geometry, textures, objects and camera), the frame,
// the stereo view, the pipeline settings and the renderer's version
// (version.h). Not the executable: a rebuild after editing a scheme or the
// timing model keeps every cached trace; a renderer change bumps the version.
//
// A stale or corrupt entry is a miss, never a wrong answer and never a
// crash: an entry is read only from a regular file no larger than the cache,
// it carries the key it was stored under and a checksum of its payload, and
// the trace it holds must be one the renderer could have made of the scene,
// frame, view and settings asked for. An entry that fails any of these is
// reported (TraceLookup::rejected), removed and rendered again. The entry's
// bytes and their checks are trace_format.h's; this file keeps the folder.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "oovr/pipeline/frame_trace.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/pipeline/trace_format.h"
#include "oovr/pipeline/version.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

// A hash of everything in the scene that a render depends on.
uint64_t scene_fingerprint(const Scene& s);

struct TraceLookup {
  std::optional<FrameTrace> trace;  // a hit
  // Why an entry stored under the key was not used (empty for a hit or when
  // there was no entry); the entry has been removed when it could be.
  std::string rejected;
};

class TraceCache {
 public:
  // `directory` empty: $OOVR_CACHE_DIR, else $XDG_CACHE_HOME/oovr/traces,
  // else ~/.cache/oovr/traces. The cache holds at most $OOVR_CACHE_MAX_MB
  // megabytes (default 8192, at least 1): storing a trace drops the least
  // recently used others until it fits; a trace larger than the whole cache
  // is not stored, and no file larger than it is read. The default holds
  // the paper's evaluation (experiments/paper.toml: 132 traces, 3.1 GB with
  // every level installed): with less, each `oovr paper` renders most of
  // them again, since the least recently used trace is the next it needs.
  explicit TraceCache(std::string directory = {});
  const std::string& directory() const { return m_dir; }
  uint64_t max_bytes() const { return m_max_bytes; }
  void set_max_bytes(uint64_t b) { m_max_bytes = b; }

  // The key of a trace; `pipeline_version` is kPipelineVersion but for tests.
  static std::string key(uint64_t scene_fingerprint, int frame, const StereoView& view, const PipelineSettings& s,
                         uint32_t pipeline_version = kPipelineVersion);
  // The trace stored under `key`, if it verifies as a trace of `frame` of
  // `scene` seen through `view` with `settings` (trace_mismatch).
  TraceLookup load(const std::string& key, const Scene& scene, int frame, const StereoView& view,
                   const PipelineSettings& settings) const;
  // Best effort: a cache that cannot be written is skipped, not an error.
  // Written aside and renamed, so readers never see half an entry; also
  // removes what interrupted stores left behind (trim).
  bool store(const std::string& key, const FrameTrace& t) const;
  // A name in the cache folder for something this process writes and
  // removes (STEM.tmp.HOST.PID): if the process dies first, a later store
  // removes it, file or folder (trim).
  std::string temporary_path(const std::string& stem) const;

 private:
  void trim(const std::filesystem::path& keep) const;

  std::string m_dir;
  uint64_t m_max_bytes = uint64_t(8192) << 20;
};

}  // namespace oovr
