#include "oovr/experiments/frames.h"

#include "oovr/core/error.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/pipeline/trace_cache.h"

namespace oovr {

FrameWindow load_window(Scene scene, const StereoRig& rig, const Config& config, const WindowRequest& r) {
  FrameWindow f{std::move(scene), rig, {}, {}, 0, {}};
  Config probe = config;  // reading the line size must not mark keys used in the caller's config
  PipelineSettings p = PipelineSettings::from_config(probe);
  p.max_anisotropy = r.aniso;
  p.line_bytes = uint32_t(MemorySpec::from_config(probe).line.value);
  p.validate();
  const int path = int(f.scene.camera.frames.size());
  if (r.first < 0 || r.first >= path)
    throw Error("frame " + std::to_string(r.first) + " is out of range: the camera path has " + std::to_string(path) + " frames");
  const TraceCache cache;
  const uint64_t fingerprint = r.use_cache ? scene_fingerprint(f.scene) : 0;
  f.outputs.reserve(size_t(r.count));
  std::vector<std::string> rejected;  // entries that did not verify
  for (int k = 0; k < r.count; ++k) {
    const int frame = (r.first + k) % path;
    const StereoView view = make_stereo_view(f.scene.camera, frame, f.rig);
    const std::string key = cache.key(fingerprint, frame, view, p);
    if (r.use_cache && !(k == 0 && r.need_first_image)) {
      TraceLookup hit = cache.load(key, f.scene, frame, view, p);
      if (!hit.rejected.empty()) rejected.push_back(std::move(hit.rejected));
      if (hit.trace) {
        FrameOutput o;
        o.trace = std::move(*hit.trace);
        f.outputs.push_back(std::move(o));
        ++f.cached;
        continue;
      }
    }
    f.outputs.push_back(render_frame(f.scene, view, p, frame));
    if (r.use_cache) cache.store(key, f.outputs.back().trace);
  }
  for (const auto& o : f.outputs) f.traces.push_back(&o.trace);
  // Once per window, however many entries: they were rendered again, so the
  // results are those of an uncached run.
  if (!rejected.empty()) {
    std::string note = "trace cache " + cache.directory() + ": " + std::to_string(rejected.size()) +
                       (rejected.size() == 1 ? " entry" : " entries") + " did not verify and " +
                       (rejected.size() == 1 ? "was" : "were") + " rendered again (" + rejected.front();
    if (rejected.size() > 1) note += "; and " + std::to_string(rejected.size() - 1) + " more";
    f.notes.push_back(note + ")");
  }
  return f;
}

}  // namespace oovr
