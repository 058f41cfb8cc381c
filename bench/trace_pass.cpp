// oovr-trace-pass: the functional pass drawing frames as their trace alone
// (PipelineSettings::draw_image off), what `oovr simulate`, `compare` and a
// cold sweep draw for every frame (docs/performance.md, "The trace pass in
// fewer instructions"). It times the pass per frame, and after loading the
// scene runs nothing else but a checksum of each frame's lines, so that its
// instructions can be counted under cachegrind: the instructions of N frames
// less those of one are the pass's and the checksum's (1.7% on oa:oa_dm4). It
// prints the frames' texture lines and their checksum, which a change that
// leaves the trace as it was must leave as they were.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/core/hash.h"
#include "oovr/core/parallel.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/run/frames.h"
#include "oovr/scene/load.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/machine_spec.h"

int main(int argc, char** argv) {
  using namespace oovr;
  std::string scene_spec = "courtyard", resolution = "1280x1024";
  int frames = 1, repeats = 1, aniso = 1;
  unsigned threads = 0;
  CLI::App app{"oovr-trace-pass: frames drawn as their trace alone, timed per frame (docs/performance.md)"};
  app.add_option("--scene", scene_spec, "Scene name or model file")->capture_default_str();
  app.add_option("--resolution", resolution, "The whole stereo frame, WxH")->capture_default_str();
  app.add_option("--frames", frames, "Frames drawn, from frame 0")->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--repeats", repeats, "Repetitions (the median is reported)")->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--threads", threads, "Threads (0: every core)")->capture_default_str()->check(CLI::Range(0u, 1024u));
  app.add_option("--aniso", aniso, "Anisotropic filtering taps")->capture_default_str()->check(CLI::Range(1, 16));
  CLI11_PARSE(app, argc, argv);
  try {
    const StereoRig rig = parse_frame_resolution(resolution);
    const Scene scene = load_scene(scene_spec);
    // As `oovr simulate` draws: the machine's line size and texture format.
    PipelineSettings settings = trace_settings(MachineSpec::from_config(Config{}), aniso);
    settings.threads = threads ? threads : default_thread_count();
    settings.draw_image = false;
    const int path = int(scene.camera.frames.size());
    std::vector<double> per_frame;
    uint64_t lines = 0;
    std::vector<uint64_t> sums;  // each frame's lines' checksum
    for (int r = 0; r < repeats; ++r) {
      lines = 0;
      sums.clear();
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < frames; ++k) {
        const int frame = k % path;
        const FrameOutput out = render_frame(scene, make_stereo_view(scene.camera, frame, rig), settings, frame);
        const auto& l = out.trace.tex_lines;
        lines += l.size();
        sums.push_back(checksum64({reinterpret_cast<const char*>(l.data()), l.size() * sizeof(TexLine)}));
      }
      per_frame.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / frames);
    }
    const uint64_t hash = checksum64({reinterpret_cast<const char*>(sums.data()), sums.size() * sizeof(uint64_t)});
    std::sort(per_frame.begin(), per_frame.end());
    fmt::print(
        "{}: {} frame{} at {}, {} thread{}: {:.1f} ms a frame (median of {}; {:.1f} to {:.1f}); {} texture lines, checksum "
        "{:016x}\n",
        scene_spec, frames, frames == 1 ? "" : "s", resolution, settings.threads, settings.threads == 1 ? "" : "s",
        per_frame[per_frame.size() / 2] * 1e3, repeats, per_frame.front() * 1e3, per_frame.back() * 1e3, lines, hash);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "oovr-trace-pass: error: {}\n", e.what());
    return 1;
  }
}
