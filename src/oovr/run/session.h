// Scenes and traces kept in memory between simulations of one process (the
// Python module's session, docs/python.md): a loop over configurations
// loads each scene once and renders each frame once, then replays it for
// every configuration and scheme. Below it the on-disk trace cache still
// serves what another process rendered.
//
// A window of traces is held under a key made of the scene's name and the
// trace cache's key of its first frame (scene content aside: the view, the
// pipeline settings and the renderer's version), so two configurations that
// render the same traces share them and two that do not (another line size,
// texture format, resolution or filtering) never do. Windows are dropped,
// least recently used first, when the traces held exceed the budget
// ($OOVR_TRACE_MEMORY_MB, default 4096, as for one window).
#pragma once

#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "oovr/run/frames.h"

namespace oovr {

class TraceSession {
 public:
  // `budget` bytes of traces held (0: $OOVR_TRACE_MEMORY_MB megabytes).
  explicit TraceSession(uint64_t budget = 0) : m_budget(budget) {}

  // The scene `spec` (load_scene's names), loaded on first use.
  std::shared_ptr<const Scene> scene(const std::string& spec);
  // The traces of `r.count` frames from `r.first` of scene `spec` with
  // `config`'s pipeline settings: a window held that covers them (as many
  // frames or more from the same first frame, with its first image when
  // `r.need_first_image`), else a new one, loaded through the trace cache
  // and then held. A window with `r.use_cache` false is rendered again and
  // replaces what was held.
  std::shared_ptr<const FrameWindow> window(const std::string& spec, const StereoRig& rig, const MachineSpec& machine,
                                            const WindowRequest& r);
  std::shared_ptr<const FrameWindow> window(const std::string& spec, const StereoRig& rig, const Config& config,
                                            const WindowRequest& r);
  // Drops every scene and window held.
  void clear();

  struct Stats {
    uint64_t scenes_loaded = 0;     // scenes read from their files or made
    uint64_t frames_rendered = 0;   // traces made by the renderer
    uint64_t frames_from_disk = 0;  // traces read from the trace cache
    uint64_t windows_reused = 0;    // requests answered from memory
    uint64_t windows_held = 0;      // now
    uint64_t bytes_held = 0;        // of traces, now
  };
  Stats stats() const;

 private:
  struct Held {
    std::shared_ptr<const FrameWindow> window;
    uint64_t bytes = 0;
  };
  void evict_locked();

  uint64_t m_budget;
  mutable std::mutex m_mutex;
  std::map<std::string, std::shared_ptr<const Scene>> m_scenes;
  std::map<std::string, Held> m_windows;
  std::list<std::string> m_recent;  // window keys, most recently used first
  Stats m_stats;
};

}  // namespace oovr
