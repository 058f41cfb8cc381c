// The traces a simulation replays: `count` consecutive frames of a scene's
// camera path (wrapping around), from the on-disk trace cache when they are
// there, rendered and cached otherwise (render once, replay per scheme).
#pragma once

#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

struct FrameWindow {
  Scene scene;
  StereoRig rig;
  std::vector<FrameOutput> outputs;  // image and object ids only where rendered
  std::vector<const FrameTrace*> traces;
  int cached = 0;  // traces that came from the cache
  // What the user should know about how the traces were got (a cache entry
  // that did not verify and was rendered again).
  std::vector<std::string> notes;
};

struct WindowRequest {
  int first = 0;
  int count = 1;
  int aniso = 16;
  bool use_cache = true;
  bool need_first_image = false;  // render frame `first` even when cached
};

// Loads the traces for `scene` (already loaded) with the memory system's
// line size from `config`. Throws Error when `first` is off the path.
FrameWindow load_window(Scene scene, const StereoRig& rig, const Config& config, const WindowRequest& r);

}  // namespace oovr
