// One scheme's run over a window of frames (run_scheme_window, i_scheme.h),
// taken a step at a time, so that a caller running several schemes on a few
// threads (oovr compare: run/simulation.cpp) can interleave their steps and
// no long run is left to go on alone at the end. A step runs one group of
// frames (one frame, or m for a scheme with m frames in flight) on the run's
// one memory system: the warm-up pass's groups, then the measured pass's.
// Taking the steps one after the other, on any thread, gives what
// run_scheme_window gives, bit for bit: it is what run_scheme_window does.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "oovr/schemes/i_scheme.h"

namespace oovr {

class WindowRun {
 public:
  // Checks the window against the scheme (a multiple of its frames in
  // flight, enough frames) and throws Error when it is not. `share`, when
  // given, as run_scheme_window's: kept by the caller until done(); its
  // `use` and `why` are set when a played run's calls differ from the tape
  // (then, or here for a tape of another key), its tape and `use` by the
  // last step otherwise.
  WindowRun(SchemeRef scheme, const Scene& scene, const FrameSequence& frames, const MachineSpec& spec, int window,
            SharedReplay* share = nullptr);
  ~WindowRun();
  WindowRun(const WindowRun&) = delete;
  WindowRun& operator=(const WindowRun&) = delete;

  bool done() const;
  // Steps left (both passes; a played run whose calls differ from its tape
  // starts again in full, and has more left than it had).
  size_t steps_left() const;
  // Runs the next step (not when done). Throws Error as run_scheme_window;
  // after a step has thrown, the run takes no more.
  void step();
  // After done(), once: the window's result, and each measured run's in
  // `runs`.
  SchemeResult result(std::vector<SchemeResult>* runs = nullptr);

 private:
  struct State;
  std::unique_ptr<State> m;
};

}  // namespace oovr
