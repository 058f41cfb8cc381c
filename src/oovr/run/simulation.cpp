#include "oovr/run/simulation.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <chrono>

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
  s.window = session ? session->window(r.scene, r.rig, machine, w)
                     : std::make_shared<const FrameWindow>(
                           load_window(std::make_shared<const Scene>(load_scene(r.scene)), r.rig, machine, w));
  const auto t1 = std::chrono::steady_clock::now();
  // Schemes are independent runs: in parallel, each into its own slot.
  s.results.resize(schemes.size());
  std::atomic<size_t> done{0};
  say(fmt::format("simulating {} scheme{} on {}", schemes.size(), schemes.size() == 1 ? "" : "s", frames));
  parallel_for(schemes.size(), r.jobs, [&](size_t i) {
    s.results[i] = run_scheme_window(schemes[i], *s.window->scene, *s.window->frames, machine, s.frames);
    say(fmt::format("{} of {} schemes simulated ({} done)", ++done, schemes.size(), schemes[i].name));
  });
  const auto t2 = std::chrono::steady_clock::now();
  s.trace_s = std::chrono::duration<double>(t1 - t0).count();
  s.simulation_s = std::chrono::duration<double>(t2 - t1).count();
  return s;
}

std::vector<std::string> default_compare_schemes() { return schemes_in_order(); }

}  // namespace oovr
