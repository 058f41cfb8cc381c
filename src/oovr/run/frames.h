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
FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const MachineSpec& spec,
                        const WindowRequest& r);
FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const Config& config, const WindowRequest& r);

}  // namespace oovr
