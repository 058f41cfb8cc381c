// Points that kill their process (docs/reliability.md, "Points that kill
// their process"). A defect that crashes oovr, or the kernel's OOM killer
// when a memory limit is reached (a cgroup's: containers, SLURM), ends the
// process at once, with no chance to record why; run in-process, such a
// point was never stored and killed every --resume again. So the local
// sweep runs its points in a child process: the database marks the points
// in flight (ResultsDb::mark_in_flight), and when a child dies of a signal,
// this parent records the point it was running as failed, with how it
// died, and goes on in a new child. When several points were in flight,
// each is run again alone first (the one that dies again is the one).
//
// Where the parent dies with its child (the whole process group killed, as
// a cgroup's OOM kill of a job can), the marks stay: the next --resume
// counts a death against each point marked, runs them alone first, and
// records a point that has died twice as failed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"

namespace oovr {

struct SuperviseOptions {
  std::string db;                      // the database
  const DatabaseLock* lock = nullptr;  // the writer's lock on it, held by the caller (children share it)
  unsigned jobs = 0;                   // points at once (0: every core)
  std::string command;                 // recorded with the failed records this writes
  // What a child does: run `which` (indices into the sweep's points) `jobs`
  // at a time, storing each record in the database (opened under `lock`).
  // An Error it throws is printed by the child, which then exits 1.
  std::function<void(const std::vector<size_t>& which, unsigned jobs)> run;
  // Lines for the user: a point recorded as failed, points run again alone.
  std::function<void(const std::string&)> note;
};

// Runs `todo` (indices into s.points) as above until every one has a
// record. Returns 0, or the exit status to give: 1 when a child ended with
// an error of its own (not a point's failure), 128 + N when interrupted by
// signal N (SIGINT, SIGTERM, SIGHUP: passed on to the child, no point
// blamed).
int supervise_points(const Sweep& s, const std::vector<size_t>& todo, const SuperviseOptions& o);

// What a record of a point whose process died of `signal` says.
std::string death_reason(int signal);

}  // namespace oovr
