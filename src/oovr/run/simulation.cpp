#include "oovr/run/simulation.h"

#include <algorithm>
#include <chrono>

#include "oovr/core/parallel.h"
#include "oovr/scene/load.h"

namespace oovr {

Simulation run_simulation(const SimulationRequest& r, const std::vector<SchemeRef>& schemes, const Config& config,
                          TraceSession* session) {
  if (schemes.empty()) throw Error("no scheme to simulate");
  const MachineSpec machine = MachineSpec::from_config(config);  // read once, for every scheme
  Simulation s;
  s.frame = r.frame;
  s.frames = measured_window(schemes, machine, r.frames, r.frames_option);
  WindowRequest w;
  w.first = r.frame;
  w.count = s.frames;
  w.aniso = r.aniso;
  w.use_cache = r.use_cache;
  w.need_first_image = r.need_first_image;
  const auto t0 = std::chrono::steady_clock::now();
  s.window = session ? session->window(r.scene, r.rig, machine, w)
                     : std::make_shared<const FrameWindow>(
                           load_window(std::make_shared<const Scene>(load_scene(r.scene)), r.rig, machine, w));
  const auto t1 = std::chrono::steady_clock::now();
  // Schemes are independent runs: in parallel, each into its own slot.
  s.results.resize(schemes.size());
  parallel_for(schemes.size(), r.jobs, [&](size_t i) {
    s.results[i] = run_scheme_window(schemes[i], *s.window->scene, *s.window->frames, machine, s.frames);
  });
  const auto t2 = std::chrono::steady_clock::now();
  s.trace_s = std::chrono::duration<double>(t1 - t0).count();
  s.simulation_s = std::chrono::duration<double>(t2 - t1).count();
  return s;
}

std::vector<std::string> default_compare_schemes() { return schemes_in_order(); }

}  // namespace oovr
