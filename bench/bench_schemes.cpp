// Scheme replay speed: one 1280x1024 courtyard frame (rendered once, outside
// the timing) through each scheme on the paper's Table 1 machine, on one
// core. What `oovr compare` costs per frame and scheme once the trace is
// cached. Counters: simulated work units and line accesses per second.
// `law_check_cost` measures what checking the conservation laws
// (schemes/conservation.h) adds to a run.
#include <benchmark/benchmark.h>

#include <chrono>

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

// What checking costs, measured as one run checked and one unchecked in turn
// within each iteration, so that a busy or throttled machine slows both
// alike: `checked_over_unchecked` is their time ratio (1.01: 1% more).
void law_check_cost(benchmark::State& state, const char* name) {
  const Frames& f = frames();
  const Config c;
  const int needed = scheme_frames_needed(name, c);
  const std::vector<const FrameTrace*> traces(f.traces.begin(), f.traces.begin() + needed);
  double on = 0, off = 0;
  for (auto _ : state) {
    for (bool check : {true, false}) {
      FrameSim::set_law_checks(check);
      const auto t0 = std::chrono::steady_clock::now();
      const SchemeResult r = run_scheme(name, f.scene, traces, c);
      benchmark::DoNotOptimize(r.frame_latency_s);
      (check ? on : off) += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  }
  FrameSim::set_law_checks(true);
  state.counters["checked_over_unchecked"] = on / off;
}

BENCHMARK_CAPTURE(scheme, baseline, "baseline")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, afr, "afr")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, sfr_v, "sfr-v")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, sfr_h, "sfr-h")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, object, "object")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, ideal, "ideal")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(scheme, oo_vr, "oo-vr")->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(law_check_cost, baseline, "baseline")->Unit(benchmark::kMillisecond)->MinTime(4.0);
BENCHMARK_CAPTURE(law_check_cost, object, "object")->Unit(benchmark::kMillisecond)->MinTime(4.0);
BENCHMARK_CAPTURE(law_check_cost, oo_vr, "oo-vr")->Unit(benchmark::kMillisecond)->MinTime(4.0);

}  // namespace
