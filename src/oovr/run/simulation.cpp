#include "oovr/run/simulation.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>

#include "oovr/core/parallel.h"
#include "oovr/scene/load.h"
#include "oovr/schemes/window_run.h"

namespace oovr {

namespace {

// The schemes' runs over the window, on up to `jobs` threads, each into its
// own slot of `s`. They are independent runs, so the results do not depend
// on how they are scheduled. Each run is taken a step (a group of frames)
// at a time (schemes/window_run.h), and a free thread takes a step of the
// run with the most work left (core/parallel.h, run_steps). Handing out
// whole runs instead left the longest (OO-VR's, twice the others' on
// oa:oa_dm4) to run alone at the end whenever it came late in the order:
// `compare` on oa:oa_dm4, 8 frames, traces cached, two cores, medians of
// alternated runs: all 17 schemes 3.12 -> 2.88 s, the paper's eight 1.73
// -> 1.65 s (docs/performance.md). Schemes whose runs may share a memory
// replay (the baseline and baseline-1tb: schemes/memory_tape.h) share it:
// the first of each key records it, and the others begin once it is done
// and play it back (or run in full when it made none).
void run_schemes(const std::vector<SchemeRef>& schemes, const Scene& scene, const FrameSequence& frames,
                 const MachineSpec& machine, int window, unsigned jobs, const std::function<void(const std::string&)>& say,
                 Simulation& s) {
  const size_t n = schemes.size();
  SteppedJobs runs;
  runs.count = n;
  std::map<std::string, size_t> first;
  std::vector<size_t> sharing(n, 0);
  for (size_t i = 0; i < n; ++i) {
    runs.after.push_back(first.emplace(shared_replay_key(schemes[i], machine), i).first->second);
    ++sharing[runs.after[i]];
  }
  std::vector<SharedReplay> share(n);
  std::vector<std::unique_ptr<WindowRun>> run(n);
  s.results.resize(n);
  s.replays.assign(n, SharedReplay::Use::none);
  runs.step = [&](size_t i) {
    if (!run[i]) {
      const size_t leader = runs.after[i];
      if (leader != i) share[i].tape = share[leader].tape;
      const bool shares = leader != i ? bool(share[i].tape) : sharing[i] > 1;
      run[i] = std::make_unique<WindowRun>(schemes[i], scene, frames, machine, window, shares ? &share[i] : nullptr);
    }
    run[i]->step();
    if (!run[i]->done()) return false;
    s.results[i] = run[i]->result();
    s.replays[i] = share[i].use;
    run[i].reset();
    return true;
  };
  runs.steps_left = [&](size_t i) { return run[i]->steps_left(); };
  std::atomic<size_t> done{0};
  runs.done = [&](size_t i) { say(fmt::format("{} of {} schemes simulated ({} done)", ++done, n, schemes[i].name)); };
  run_steps(runs, jobs);
}

}  // namespace

Simulation run_simulation(const SimulationRequest& r, const std::vector<SchemeRef>& schemes, const Config& config,
                          TraceSession* session) {
  if (schemes.empty()) throw Error("no scheme to simulate");
  MachineSpec machine = MachineSpec::from_config(config);  // read once, for every scheme
  machine.timeline = r.timeline;
  Simulation s;
  s.frame = r.frame;
  s.frames = measured_window(schemes, machine, r.frames, r.frames_option);
  WindowRequest w;
  w.first = r.frame;
  w.count = s.frames;
  w.aniso = r.aniso;
  w.use_cache = r.use_cache;
  w.need_first_image = r.need_first_image;
  const auto say = [&](const std::string& what) {
    if (r.progress) r.progress(what);
  };
  const auto t0 = std::chrono::steady_clock::now();
  const std::string frames =
      s.frames == 1 ? fmt::format("frame {}", r.frame) : fmt::format("frames {} to {}", r.frame, r.frame + s.frames - 1);
  say("loading " + r.scene + ", then the traces of " + frames);
  // Without a session, the traces load on a thread of their own while the
  // schemes replay them: a scheme replays frame k as soon as it is there,
  // while frame k + 1 renders (WindowLoader).
  std::shared_ptr<const Scene> scene;
  std::unique_ptr<WindowLoader> loader;
  if (session) {
    s.window = session->window(r.scene, r.rig, machine, w);
    scene = s.window->scene;
  } else {
    scene = std::make_shared<const Scene>(load_scene(r.scene));
    s.trace_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    loader = std::make_unique<WindowLoader>(scene, r.rig, machine, w);
  }
  const FrameSequence& window_frames = loader ? loader->frames() : *s.window->frames;
  const auto t1 = std::chrono::steady_clock::now();
  say(fmt::format("simulating {} scheme{} on {}", schemes.size(), schemes.size() == 1 ? "" : "s", frames));
  try {
    run_schemes(schemes, *scene, window_frames, machine, s.frames, r.jobs, say, s);
  } catch (...) {
    // A scheme that waited for a frame the loader failed on rethrew its
    // error; say that error (the loader's), whichever thread saw it first.
    if (loader) loader->wait();
    throw;
  }
  const auto t2 = std::chrono::steady_clock::now();
  if (loader) {
    s.window = loader->wait();
    s.trace_s += loader->seconds();
  } else {
    s.trace_s = std::chrono::duration<double>(t1 - t0).count();
  }
  s.simulation_s = std::chrono::duration<double>(t2 - t1).count();
  return s;
}

std::vector<std::string> default_compare_schemes() { return schemes_in_order(); }

}  // namespace oovr
