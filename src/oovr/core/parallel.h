// A minimal parallel-for. Work items are independent and write only their own
// outputs, so results never depend on the thread count or on scheduling.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace oovr {

// Number of worker threads to use when the caller asks for 0 ("automatic").
unsigned default_thread_count();

// Calls fn(i) for every i in [0, n) on up to `threads` threads (0 = automatic).
// Items are handed out dynamically; fn must only write state owned by item i.
// The first exception thrown by fn is rethrown on the calling thread.
void parallel_for(size_t n, unsigned threads, const std::function<void(size_t)>& fn);

// Jobs taken a step at a time (run_steps): each job's steps run one at a
// time and in order, on any thread; each job writes only its own outputs.
struct SteppedJobs {
  size_t count = 0;
  // Runs job i's next step; true when it was the job's last.
  std::function<bool(size_t i)> step;
  // Job i's steps left, asked after each step of it that was not its last.
  std::function<size_t(size_t i)> steps_left;
  // after[i]: the job whose last step job i's first waits for (i, or an
  // empty list: none).
  std::vector<size_t> after;
  // Called when job i is done, on the thread that ran its last step, with no
  // lock held. May be empty.
  std::function<void(size_t i)> done;
};

// Runs every step of every job on up to `threads` threads (0 = automatic).
// A free thread takes a step of the job with the most work left, by
// next_step. The first exception a step or `done` throws stops the handing
// out of steps and is rethrown on the calling thread once the steps under
// way have ended.
void run_steps(const SteppedJobs& jobs, unsigned threads);

// A job as run_steps sees it when it chooses the next step.
struct StepState {
  bool running = false, done = false, waiting = false;  // waiting: for its `after` job
  size_t steps = 0;                                     // taken
  size_t left = 0;                                      // left, once one is taken
  double seconds = 0;                                   // the steps' time so far
};
// The job whose step a free thread takes: of those neither running, done
// nor waiting, one not yet begun (the first, in order), else the one with
// the most work left by its steps so far (left x seconds / steps; the first
// of equals). jobs.size() when none may take a step.
size_t next_step(const std::vector<StepState>& jobs);

}  // namespace oovr
