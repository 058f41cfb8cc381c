// The traces a simulation replays: `count` consecutive frames of a scene's
// camera path (wrapping around), from the on-disk trace cache when they are
// there, rendered and cached otherwise (render once, replay per scheme).
//
// A window whose traces would take more memory than $OOVR_TRACE_MEMORY_MB
// (default 4096) is streamed: each trace is written to a folder of its own
// beside the trace cache as it is made, and read back only while a scheme
// runs its frame, so `--frames 1000` at 1280x1024 needs disk, not tens of
// GB of memory. The numbers are the same either way.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "oovr/core/config.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct FrameWindow {
  std::shared_ptr<const Scene> scene;  // shared, not copied: a window is cheap to make from a loaded scene
  StereoRig rig;
  // In memory: every frame's output (image and object ids only for the
  // first frame, and only where rendered), and `traces` points at them. Streamed: only the first
  // frame's output; `traces` is empty.
  std::vector<FrameOutput> outputs;
  std::vector<const FrameTrace*> traces;
  // Every frame of the window, in memory or streamed: what schemes replay.
  std::shared_ptr<const FrameSequence> frames;
  int cached = 0;  // traces that came from the cache
  bool streamed = false;
  // What the user should know about how the traces were got (a cache entry
  // that did not verify and was rendered again, a streamed window).
  std::vector<std::string> notes;
};

struct WindowRequest {
  int first = 0;
  int count = 1;
  int aniso = 16;
  bool use_cache = true;
  bool need_first_image = false;  // render frame `first` even when cached
  // Bytes of traces held in memory before the window is streamed; 0:
  // $OOVR_TRACE_MEMORY_MB megabytes (default 4096).
  uint64_t memory_budget = 0;
};

// The frames every scheme of `schemes` is measured on with `config`:
// `frames` when given (> 0), which must then be a multiple of the frames
// each scheme renders at once (AFR: one per GPM; else Error naming the
// scheme, with `what` naming the setting: "--frames", "frames"); without
// it, one per GPM, so that AFR's frames in flight and every other scheme
// see the same frames. Checks each scheme's configuration first.
int measured_window(const std::vector<SchemeRef>& schemes, const MachineSpec& spec, int frames, const std::string& what);
int measured_window(const std::vector<std::string>& schemes, const MachineSpec& spec, int frames, const std::string& what);
int measured_window(const std::vector<std::string>& schemes, const Config& config, int frames, const std::string& what);

// Bytes of traces held in memory: $OOVR_TRACE_MEMORY_MB megabytes (default
// 4096). Throws Error when the variable is not a whole number.
uint64_t trace_memory_budget();
// What a trace holds in memory, as the budget counts it (its records and
// texture lines), and what a window's traces in memory hold together.
uint64_t trace_bytes(const FrameTrace& t);
uint64_t window_bytes(const FrameWindow& w);

// What the pipeline is told when it renders the traces a simulation with
// `spec` replays: the texture storage format it names, the memory
// system's line size, and `aniso` taps. Throws Error on a bad value.
PipelineSettings trace_settings(const MachineSpec& spec, int aniso);

// Loads the traces for `scene` (already loaded) with trace_settings(config).
// Throws Error when `first` is off the path, when a streamed window does
// not fit on the disk, or when memory runs out (naming the frame).
// `ready`, when given, is called with each trace held in memory as soon as
// it is there (k: its place in the window), from the calling thread; the
// trace stays where it is in the window returned.
using FrameReady = std::function<void(size_t k, const FrameTrace& trace)>;
FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const MachineSpec& spec, const WindowRequest& r,
                        const FrameReady& ready = {});
FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const Config& config, const WindowRequest& r);

// A window loaded on a thread of its own while schemes replay it (issue 31:
// the replay of frame k overlapped with rendering frame k + 1): frames()
// hands out frame k as soon as it is rendered or read from the cache, and
// waits for it until then. The traces are those load_window makes, so the
// results are the same as with the window loaded first.
class WindowLoader {
 public:
  WindowLoader(std::shared_ptr<const Scene> scene, const StereoRig& rig, const MachineSpec& spec, const WindowRequest& r);
  ~WindowLoader();  // waits for the thread
  WindowLoader(const WindowLoader&) = delete;
  WindowLoader& operator=(const WindowLoader&) = delete;

  // The window's frames, each given out once loaded; at(k) rethrows the
  // loader's error when it failed before frame k.
  const FrameSequence& frames() const { return m_frames; }
  // The whole window, once loaded (waits for it); rethrows the loader's error.
  std::shared_ptr<const FrameWindow> wait();
  // Seconds the loading took (after wait()).
  double seconds() const { return m_seconds; }

 private:
  class Frames final : public FrameSequence {
   public:
    explicit Frames(WindowLoader& owner) : m_owner(owner) {}
    size_t size() const override;
    std::shared_ptr<const FrameTrace> at(size_t k) const override;

   private:
    WindowLoader& m_owner;
  };

  size_t m_count;
  Frames m_frames;
  mutable std::mutex m_mutex;
  mutable std::condition_variable m_changed;
  std::vector<const FrameTrace*> m_ready;  // frame k once in memory
  bool m_done = false;
  std::exception_ptr m_error;
  std::shared_ptr<FrameWindow> m_filling;  // the window being filled, kept after an error too
  double m_seconds = 0;
  std::thread m_thread;
};

}  // namespace oovr
