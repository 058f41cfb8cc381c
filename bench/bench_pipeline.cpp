// Functional pipeline throughput: one stereo frame (image + FrameTrace) of
// the built-in scenes at the paper's resolutions. Compare with llvmpipe's
// time for the same frame, which `oovr-reference --compare` prints.
#include <benchmark/benchmark.h>

#include <map>

#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/builtin.h"

namespace {

using namespace oovr;

const Scene& scene(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, BuiltinScenes::find(name)->make()).first;
  return it->second;
}

void render(benchmark::State& state, const std::string& name, int width, int height, int aniso, bool lines) {
  const Scene& s = scene(name);
  StereoRig rig;
  rig.eye_width = width / 2;
  rig.eye_height = height;
  const StereoView view = make_stereo_view(s.camera, 60, rig);
  PipelineSettings p;
  p.max_anisotropy = aniso;
  p.record_texture_lines = lines;
  uint64_t fragments = 0;
  for (auto _ : state) {
    FrameOutput out = render_frame(s, view, p, 60);
    fragments = out.trace.total_covered();
    benchmark::DoNotOptimize(out);
  }
  state.counters["fragments"] = double(fragments);
  state.counters["Mfrag/s"] =
      benchmark::Counter(double(fragments) * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(render, courtyard_1280x1024_aniso1, "courtyard", 1280, 1024, 1, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(render, courtyard_1280x1024_aniso1_notrace, "courtyard", 1280, 1024, 1, false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(render, courtyard_1280x1024_aniso16, "courtyard", 1280, 1024, 16, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(render, courtyard_640x480_aniso1, "courtyard", 640, 480, 1, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(render, courtyard_1600x1200_aniso1, "courtyard", 1600, 1200, 1, true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(render, crowd_1280x1024_aniso1, "crowd", 1280, 1024, 1, true)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
