#include "oovr/run/simulation.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <map>

#include "oovr/core/parallel.h"
#include "oovr/scene/load.h"

namespace oovr {

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
  // Schemes are independent runs: in parallel, each into its own slot.
  // Schemes whose runs may share a memory replay (the baseline and
  // baseline-1tb: schemes/memory_tape.h) share it: the first of them
  // records it, the others play it back once it is made. The first of
  // each key starts before any other, so that nobody waits for a run not
  // yet begun.
  const size_t n = schemes.size();
  std::vector<std::string> keys(n);
  std::map<std::string, size_t> first;
  std::vector<size_t> order, sharing(n, 0);
  for (size_t i = 0; i < n; ++i) {
    keys[i] = shared_replay_key(schemes[i], machine);
    if (first.emplace(keys[i], i).second) order.push_back(i);
    ++sharing[first[keys[i]]];
  }
  for (size_t i = 0; i < n; ++i)
    if (first[keys[i]] != i) order.push_back(i);
  std::vector<std::promise<std::shared_ptr<const MemoryTape>>> recorded(n);
  std::vector<std::shared_future<std::shared_ptr<const MemoryTape>>> tapes;
  for (auto& p : recorded) tapes.push_back(p.get_future().share());
  s.results.resize(n);
  s.replays.assign(n, SharedReplay::Use::none);
  std::atomic<size_t> done{0};
  say(fmt::format("simulating {} scheme{} on {}", n, n == 1 ? "" : "s", frames));
  const auto schemes_run = [&](size_t k) {
    const size_t i = order[k], leader = first[keys[i]];
    SharedReplay share;
    if (leader != i) share.tape = tapes[leader].get();
    const bool shares = leader != i ? bool(share.tape) : sharing[i] > 1;
    try {
      s.results[i] = run_scheme_window(schemes[i], *scene, window_frames, machine, s.frames, nullptr, shares ? &share : nullptr);
    } catch (...) {
      if (leader == i) recorded[i].set_value(nullptr);  // the others run in full
      throw;
    }
    if (leader == i) recorded[i].set_value(share.tape);
    s.replays[i] = share.use;
    say(fmt::format("{} of {} schemes simulated ({} done)", ++done, n, schemes[i].name));
  };
  try {
    parallel_for(n, r.jobs, schemes_run);
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
