#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/core/parallel.h"

namespace oovr {
namespace {

StepState begun(size_t steps, size_t left, double seconds) {
  StepState s;
  s.steps = steps;
  s.left = left;
  s.seconds = seconds;
  return s;
}

TEST(Parallel, AFreeThreadTakesTheJobWithTheMostWorkLeft) {
  // Left x mean step: 3 x 1.0 = 3, 10 x 0.1 = 1, 2 x 2.5 = 5.
  std::vector<StepState> jobs = {begun(2, 3, 2.0), begun(4, 10, 0.4), begun(2, 2, 5.0)};
  EXPECT_EQ(next_step(jobs), 2u);
  jobs[2].running = true;
  EXPECT_EQ(next_step(jobs), 0u);
  jobs[0].done = true;
  EXPECT_EQ(next_step(jobs), 1u);
  jobs[1].waiting = true;
  EXPECT_EQ(next_step(jobs), jobs.size());
  // A job not yet begun comes before any begun (its work is not known),
  // the first of them in order; equals go by order too.
  std::vector<StepState> fresh = {begun(5, 100, 50.0), StepState{}, StepState{}};
  EXPECT_EQ(next_step(fresh), 1u);
  fresh[1].waiting = true;
  EXPECT_EQ(next_step(fresh), 2u);
  EXPECT_EQ(next_step({begun(1, 2, 1.0), begun(2, 2, 2.0)}), 0u);
  EXPECT_EQ(next_step({}), 0u);
}

TEST(Parallel, EveryStepRunsOnceInOrderAndAJobWaitsForItsAfter) {
  // Jobs of 3 to 14 steps on 1, 2 and 5 threads: each job's steps run in
  // order, never two at once, and a job's first step only after the last
  // of the job it waits for.
  for (unsigned threads : {1u, 2u, 5u}) {
    const size_t n = 9;
    std::vector<size_t> length(n), taken(n, 0);
    std::vector<std::atomic<int>> inside(n);
    std::vector<int> finished_at(n, -1), started_at(n, -1), done_calls(n, 0);
    std::atomic<int> clock{0};
    std::atomic<bool> overlap{false};
    for (size_t i = 0; i < n; ++i) length[i] = 3 + (i * 5) % 12;
    SteppedJobs jobs;
    jobs.count = n;
    jobs.after = {0, 0, 2, 3, 0, 5, 3, 7, 8};  // 1 and 4 wait for 0, 3 for 2, 6 for 3
    jobs.step = [&](size_t i) {
      if (inside[i].fetch_add(1) != 0) overlap = true;
      if (taken[i] == 0) started_at[i] = clock++;
      std::this_thread::sleep_for(std::chrono::microseconds(50 * (i % 3)));
      const bool last = ++taken[i] == length[i];
      if (last) finished_at[i] = clock++;
      inside[i].fetch_sub(1);
      return last;
    };
    jobs.steps_left = [&](size_t i) { return length[i] - taken[i]; };
    std::mutex m;
    jobs.done = [&](size_t i) {
      std::lock_guard<std::mutex> lock(m);
      ++done_calls[i];
    };
    run_steps(jobs, threads);
    EXPECT_FALSE(overlap) << threads;
    for (size_t i = 0; i < n; ++i) {
      EXPECT_EQ(taken[i], length[i]) << i << " on " << threads;
      EXPECT_EQ(done_calls[i], 1) << i << " on " << threads;
      if (jobs.after[i] != i) {
        EXPECT_GT(started_at[i], finished_at[jobs.after[i]]) << i << " on " << threads;
      }
    }
  }
}

TEST(Parallel, AStepsErrorStopsTheStepsAndIsRethrown) {
  // Four jobs of 300 steps; job 1's first throws. The steps under way end
  // and no other begins: far fewer than the 900 the others have left (a
  // thread may begin a step or two before the error is seen).
  for (unsigned threads : {1u, 3u}) {
    std::atomic<int> after_error{0};
    std::atomic<bool> thrown{false};
    std::vector<size_t> taken(4, 0);
    SteppedJobs jobs;
    jobs.count = 4;
    jobs.step = [&](size_t i) -> bool {
      if (thrown) ++after_error;
      if (i == 1) {
        thrown = true;
        throw Error("job 1 failed");
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      return ++taken[i] == 300;
    };
    jobs.steps_left = [&](size_t i) { return 300 - taken[i]; };
    try {
      run_steps(jobs, threads);
      ADD_FAILURE() << "no error on " << threads;
    } catch (const Error& e) {
      EXPECT_STREQ(e.what(), "job 1 failed");
    }
    EXPECT_LT(after_error.load(), 100) << threads;
  }
}

TEST(Parallel, JobsThatWaitForEachOtherAreRefused) {
  SteppedJobs jobs;
  jobs.count = 2;
  jobs.after = {1, 0};
  jobs.step = [](size_t) { return true; };
  jobs.steps_left = [](size_t) { return size_t(0); };
  EXPECT_THROW(run_steps(jobs, 2), Error);
  jobs.after = {0, 2};
  EXPECT_THROW(run_steps(jobs, 2), Error);
}

}  // namespace
}  // namespace oovr
