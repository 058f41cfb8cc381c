#include "oovr/core/parallel.h"

#include "oovr/core/error.h"
#include "oovr/core/text.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <new>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace oovr {

unsigned default_thread_count() {
  if (const char* env = std::getenv("OOVR_THREADS")) {
    const auto n = parse_whole_number(env, 1, 1024);
    if (!n) throw Error(std::string("OOVR_THREADS must be a whole number from 1 to 1024, not '") + env + "'");
    return unsigned(*n);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

namespace {

// Runs `worker` on `threads` threads, this one among them, and waits for all.
// The workers share the work out among themselves, so when the system will
// not start another thread the ones started (this one at least) do it all.
template <typename F>
void on_threads(unsigned threads, F& worker) {
  std::vector<std::thread> pool;
  try {
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  } catch (const std::system_error&) {
  } catch (const std::bad_alloc&) {
  }
  worker();
  for (auto& t : pool) t.join();
}

}  // namespace

void parallel_for(size_t n, unsigned threads, const std::function<void(size_t)>& fn) {
  if (threads == 0) threads = default_thread_count();
  threads = unsigned(std::min<size_t>(threads, n));
  if (threads <= 1) {
    for (size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (;;) {
      const size_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= n) return;
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(n);
        return;
      }
    }
  };
  on_threads(threads, worker);
  if (error) std::rethrow_exception(error);
}

size_t next_step(const std::vector<StepState>& jobs) {
  size_t best = jobs.size();
  double most = -1;
  for (size_t i = 0; i < jobs.size(); ++i) {
    const StepState& j = jobs[i];
    if (j.running || j.done || j.waiting) continue;
    if (j.steps == 0) return i;
    const double left = double(j.left) * j.seconds / double(j.steps);
    if (left > most) {
      best = i;
      most = left;
    }
  }
  return best;
}

void run_steps(const SteppedJobs& jobs, unsigned threads) {
  const size_t n = jobs.count;
  if (!jobs.after.empty() && jobs.after.size() != n) throw Error("run_steps: one `after` per job, or none");
  std::vector<StepState> state(n);
  for (size_t i = 0; i < n; ++i) {
    if (!jobs.after.empty() && jobs.after[i] >= n) throw Error("run_steps: a job waits for one that is not there");
    state[i].waiting = !jobs.after.empty() && jobs.after[i] != i;
  }
  std::mutex mutex;
  std::condition_variable changed;
  std::exception_ptr error;
  size_t done = 0;
  const auto worker = [&] {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      if (error || done == n) return;
      const size_t i = next_step(state);
      if (i == n) {
        bool running = false;
        for (const StepState& s : state) running = running || s.running;
        if (!running) {  // every job left waits for another left: none would ever start
          error = std::make_exception_ptr(Error("run_steps: the jobs left wait for each other"));
          changed.notify_all();
          return;
        }
        changed.wait(lock);
        continue;
      }
      state[i].running = true;
      lock.unlock();
      const auto t0 = std::chrono::steady_clock::now();
      bool last = false;
      size_t left = 0;
      try {
        last = jobs.step(i);
        if (!last) left = jobs.steps_left(i);
        if (last && jobs.done) jobs.done(i);
      } catch (...) {
        lock.lock();
        if (!error) error = std::current_exception();
        changed.notify_all();
        return;
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      lock.lock();
      StepState& s = state[i];
      s.running = false;
      s.done = last;
      s.left = left;
      s.seconds += seconds;
      ++s.steps;
      if (last) {
        ++done;
        for (size_t k = 0; k < n; ++k)
          if (state[k].waiting && jobs.after[k] == i) state[k].waiting = false;
      }
      changed.notify_all();
    }
  };
  if (threads == 0) threads = default_thread_count();
  on_threads(unsigned(std::max<size_t>(1, std::min<size_t>(threads, n))), worker);
  if (error) std::rethrow_exception(error);
}

}  // namespace oovr
