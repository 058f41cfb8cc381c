// One simulation as `oovr simulate` and `oovr compare` run it, and as the
// Python module's simulate() and compare() run it: the traces of a window
// of frames (rendered once, or from the trace cache, or held by a session),
// replayed through each scheme, the schemes in parallel. The CLI prints
// what this returns (result_text.h); the Python module hands it over.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/run/frames.h"
#include "oovr/run/session.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct SimulationRequest {
  std::string scene;  // as load_scene takes it
  StereoRig rig;      // 1280x1024 stereo unless set
  int frame = 0;      // first frame of the camera path
  int frames = 0;     // frames measured; 0: one per GPM (measured_window)
  int aniso = 16;
  bool use_cache = true;                   // the on-disk trace cache
  bool need_first_image = false;           // the first frame's picture, for GPM and traffic images
  unsigned jobs = 0;                       // threads the schemes' runs share, a frame at a time (0: every core)
  std::string frames_option = "--frames";  // how messages name `frames`
  bool timeline = false;                   // keep every unit's time (SchemeResult::timeline)
  // What the simulation is doing, as it moves on (loading, traces, each
  // scheme done); called from the schemes' threads too. Empty: nothing.
  std::function<void(const std::string&)> progress;
};

struct Simulation {
  std::shared_ptr<const FrameWindow> window;
  int frame = 0;                      // first frame measured
  int frames = 0;                     // frames measured
  std::vector<SchemeResult> results;  // in the order the schemes were given
  // How each scheme's memory replay went (schemes/memory_tape.h): none,
  // recorded for another scheme, played back from one, or run in full
  // after its calls differed. The results are the same either way.
  std::vector<SharedReplay::Use> replays;
  // Loading the scene and getting its traces, and replaying them. Without a
  // session the two overlap: the schemes start on the first frame while
  // the others render, and simulation_s includes their waits for frames.
  double trace_s = 0;
  double simulation_s = 0;
};

// Checks every scheme against `config` (before any trace is rendered), gets
// the window's traces (through `session` when given, else loaded for this
// call) and runs each scheme over them. Throws Error naming what is wrong.
Simulation run_simulation(const SimulationRequest& r, const std::vector<SchemeRef>& schemes, const Config& config,
                          TraceSession* session = nullptr);

// What `oovr compare` runs without --schemes: the paper's schemes in the
// paper's order (Sections 3 and 4), then the bounds, then any other
// registered scheme by name.
std::vector<std::string> default_compare_schemes();

}  // namespace oovr
