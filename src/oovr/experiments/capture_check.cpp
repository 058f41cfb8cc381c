#include "oovr/experiments/capture_check.h"

#include <cstdio>
#include <filesystem>

#include "oovr/core/error.h"
#include "oovr/pipeline/image.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/formats/gl_trace.h"
#include "oovr/scene/stereo.h"

namespace oovr {

namespace {

// `v` as one view filling a window of `width` x `height` (a game's own,
// mono, no eye offset): what a capture was drawn as.
StereoView window_view(StereoView v, int width, int height) {
  v.eyes = 1;
  v.frame_width = width;
  v.frame_height = height;
  v.viewport[0] = {0, 0, width, height};
  return v;
}

}  // namespace

std::vector<CaptureFrameCheck> check_capture(const Scene& scene, const CaptureCheckOptions& o) {
  std::error_code ec;
  if (!std::filesystem::is_directory(o.snapshots, ec))
    throw Error("no folder of snapshots '" + o.snapshots +
                "' (glretrace -s DIR/ --call-nos=false writes them; scripts/capture-frames.sh keeps them beside the capture)");
  if (!scene.captured() || scene.capture_width <= 0 || scene.capture_height <= 0)
    throw Error("scene '" + scene.name +
                "' is not a captured game (trace:, oa-demo: or nexuiz-demo:): there are no snapshots to compare with");
  // One eye, the game's own view: the capture's window, no eye offset.
  const StereoView view = window_view(StereoView{}, scene.capture_width, scene.capture_height);
  PipelineSettings settings;
  settings.max_anisotropy = o.max_anisotropy;
  std::vector<CaptureFrameCheck> out;
  for (int f = 0; f < int(scene.camera.frames.size()); ++f) {
    CaptureFrameCheck c;
    c.frame = f;
    c.game_frame = scene.capture_first_frame + f;
    const GameDraws g = game_draws(scene, f);
    c.draws = g.draws;
    c.triangles = g.triangles;
    c.clears = g.clears;
    const FrameOutput img = render_frame(scene, view, settings, f);
    char name[32];
    std::snprintf(name, sizeof name, "%010d.png", c.game_frame);
    const std::string path = (std::filesystem::path(o.snapshots) / name).string();
    if (std::filesystem::exists(path, ec)) {
      const Image snap = read_png(path);
      if (snap.width != img.colour.width || snap.height != img.colour.height)
        throw Error("snapshot '" + path + "' is " + std::to_string(snap.width) + "x" + std::to_string(snap.height) +
                    ", the capture's window " + std::to_string(img.colour.width) + "x" + std::to_string(img.colour.height));
      c.snapshot = true;
      c.psnr = psnr_rgb(img.colour, snap);
    }
    if (!o.diff_dir.empty()) {
      char own[48];
      std::snprintf(own, sizeof own, "oovr-%010d.png", c.game_frame);
      write_png(img.colour, (std::filesystem::path(o.diff_dir) / own).string());
    }
    out.push_back(c);
  }
  return out;
}

std::vector<RoundTripFrame> check_round_trip(const Scene& captured, const Scene& original, int max_anisotropy) {
  if (!captured.captured() || captured.capture_width <= 0 || captured.capture_height <= 0)
    throw Error("scene '" + captured.name +
                "' is not a captured game (trace:, oa-demo: or nexuiz-demo:): there is no round trip to check");
  if (original.captured()) throw Error("scene '" + original.name + "' is itself a capture: give the scene that was captured");
  const int frames = int(captured.camera.frames.size());
  const int path = int(original.camera.frames.size());
  if (captured.capture_first_frame + frames > path)
    throw Error("the capture's frames " + std::to_string(captured.capture_first_frame) + " to " +
                std::to_string(captured.capture_first_frame + frames - 1) + " run past the " + std::to_string(path) +
                " frames of scene '" + original.name + "'");
  PipelineSettings settings;
  settings.max_anisotropy = max_anisotropy;
  StereoRig rig;
  rig.ipd_m = 0;
  rig.eye_width = captured.capture_width;
  rig.eye_height = captured.capture_height;
  const auto mono = [&](const StereoView& v) { return window_view(v, rig.eye_width, rig.eye_height); };
  const StereoView captured_view = mono(StereoView{});
  std::vector<RoundTripFrame> out;
  for (int k = 0; k < frames; ++k) {
    RoundTripFrame r;
    r.frame = captured.capture_first_frame + k;
    const FrameOutput img[2] = {render_frame(captured, captured_view, settings, k),
                                render_frame(original, mono(make_stereo_view(original.camera, r.frame, rig)), settings, r.frame)};
    const Scene* scenes[2] = {&captured, &original};
    const int frame_of[2] = {k, r.frame};
    for (int i = 0; i < 2; ++i) {
      const GameDraws g = game_draws(*scenes[i], frame_of[i]);
      r.draws[i] = g.draws;
      r.triangles[i] = g.triangles;
      r.covered[i] = img[i].trace.total_covered();
      r.passed[i] = img[i].trace.total_passed();
      r.fetches[i] = img[i].trace.layer_fetches();
    }
    r.psnr = psnr_rgb(img[0].colour, img[1].colour);
    out.push_back(r);
  }
  return out;
}

}  // namespace oovr
