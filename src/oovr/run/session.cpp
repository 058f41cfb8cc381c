#include "oovr/run/session.h"

#include "oovr/pipeline/trace_cache.h"
#include "oovr/scene/load.h"

namespace oovr {

namespace {

uint64_t bytes_of(const FrameWindow& w) {
  uint64_t b = 0;
  for (const FrameOutput& o : w.outputs) {
    b += trace_bytes(o.trace);
    b += o.colour.rgba.size() + o.object_id.size() * sizeof(uint32_t);
  }
  return b;
}

}  // namespace

std::shared_ptr<const Scene> TraceSession::scene(const std::string& spec) {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    const auto it = m_scenes.find(spec);
    if (it != m_scenes.end()) return it->second;
  }
  auto s = std::make_shared<const Scene>(load_scene(spec));  // outside the lock: loading takes a while
  std::lock_guard<std::mutex> lock(m_mutex);
  ++m_stats.scenes_loaded;
  return m_scenes.emplace(spec, std::move(s)).first->second;
}

std::shared_ptr<const FrameWindow> TraceSession::window(const std::string& spec, const StereoRig& rig, const Config& config,
                                                        const WindowRequest& r) {
  return window(spec, rig, MachineSpec::from_config(config), r);
}

std::shared_ptr<const FrameWindow> TraceSession::window(const std::string& spec, const StereoRig& rig, const MachineSpec& machine,
                                                        const WindowRequest& r) {
  const std::shared_ptr<const Scene> sc = scene(spec);
  const int path = int(sc->camera.frames.size());
  if (r.first < 0 || r.first >= path)
    throw Error("frame " + std::to_string(r.first) + " is out of range: the camera path has " + std::to_string(path) + " frames");
  // Everything that decides the traces but the scene's content, which its
  // name fixes within a session.
  const std::string key =
      spec + "\n" + TraceCache::key(0, r.first, make_stereo_view(sc->camera, r.first, rig), trace_settings(machine, r.aniso));
  if (r.use_cache) {
    std::lock_guard<std::mutex> lock(m_mutex);
    const auto it = m_windows.find(key);
    if (it != m_windows.end()) {
      const FrameWindow& w = *it->second.window;
      const bool has_image = !w.outputs.empty() && !w.outputs.front().colour.rgba.empty();
      if (int(w.frames->size()) >= r.count && (has_image || !r.need_first_image)) {
        ++m_stats.windows_reused;
        m_recent.remove(key);
        m_recent.push_front(key);
        return it->second.window;
      }
    }
  }
  auto w = std::make_shared<const FrameWindow>(load_window(sc, rig, machine, r));
  std::lock_guard<std::mutex> lock(m_mutex);
  m_stats.frames_from_disk += uint64_t(w->cached);
  m_stats.frames_rendered += uint64_t(r.count - w->cached);
  Held& h = m_windows[key];
  m_stats.bytes_held -= h.bytes;
  h = {w, bytes_of(*w)};
  m_stats.bytes_held += h.bytes;
  m_recent.remove(key);
  m_recent.push_front(key);
  evict_locked();
  return w;
}

void TraceSession::evict_locked() {
  const uint64_t budget = m_budget ? m_budget : trace_memory_budget();
  // The window just used stays, whatever its size: it is being used.
  while (m_stats.bytes_held > budget && m_recent.size() > 1) {
    const std::string victim = m_recent.back();
    m_recent.pop_back();
    m_stats.bytes_held -= m_windows[victim].bytes;
    m_windows.erase(victim);
  }
  m_stats.windows_held = m_windows.size();
}

void TraceSession::clear() {
  std::lock_guard<std::mutex> lock(m_mutex);
  m_scenes.clear();
  m_windows.clear();
  m_recent.clear();
  m_stats.bytes_held = 0;
  m_stats.windows_held = 0;
}

TraceSession::Stats TraceSession::stats() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return m_stats;
}

}  // namespace oovr
