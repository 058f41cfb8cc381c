// Scheme replay speed: one 1280x1024 courtyard frame (rendered once, outside
// the timing) through each scheme on the paper's Table 1 machine, on one
// core. What `oovr compare` costs per frame and scheme once the trace is
// cached. Counters: simulated work units and line accesses per second. The
// `_unchecked` runs turn off the conservation laws' ledger
// (schemes/conservation.h): their difference is what the check costs.
#include <benchmark/benchmark.h>

#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/builtin.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/i_scheme.h"

namespace {

using namespace oovr;

struct Frames {
  Scene scene;
  std::vector<FrameOutput> out;
  std::vector<const FrameTrace*> traces;
};

const Frames& frames() {
  static Frames* f = [] {
    auto* r = new Frames{BuiltinScenes::find("courtyard")->make(), {}, {}};
    StereoRig rig;
    rig.eye_width = 640;
    rig.eye_height = 1024;
    for (int k = 0; k < 4; ++k)
      r->out.push_back(render_frame(r->scene, make_stereo_view(r->scene.camera, k, rig), PipelineSettings{}, k));
    for (const auto& o : r->out) r->traces.push_back(&o.trace);
    return r;
  }();
  return *f;
}

void scheme(benchmark::State& state, const char* name) {
  const Frames& f = frames();
  const Config c;
  const int needed = scheme_frames_needed(name, c);
  const std::vector<const FrameTrace*> traces(f.traces.begin(), f.traces.begin() + needed);
  uint64_t units = 0;
  for (auto _ : state) {
    const SchemeResult r = run_scheme(name, f.scene, traces, c);
    units += r.units;
    benchmark::DoNotOptimize(r.frame_latency_s);
  }
  state.counters["frames"] = benchmark::Counter(double(state.iterations()) * needed, benchmark::Counter::kIsRate);
  state.counters["units"] = benchmark::Counter(double(units), benchmark::Counter::kIsRate);
}

// The same with the laws unchecked, for what checking costs (benchmarks
// only: results are always checked).
void unchecked(benchmark::State& state, const char* name) {
  FrameSim::set_law_checks(false);
  scheme(state, name);
  FrameSim::set_law_checks(true);
}

BENCHMARK_CAPTURE(scheme, baseline, "baseline")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, afr, "afr")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, sfr_v, "sfr-v")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, sfr_h, "sfr-h")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, object, "object")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, ideal, "ideal")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, oo_vr, "oo-vr")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(unchecked, baseline_unchecked, "baseline")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(unchecked, object_unchecked, "object")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(unchecked, oo_vr_unchecked, "oo-vr")->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
