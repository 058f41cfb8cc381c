// The sweep engine: runs resolved sweep points and hands each outcome over
// as a RunRecord (results_db.h), done or failed. Points that replay the
// same traces (trace_group) share them: their scene is loaded and their
// traces rendered (or read from the trace cache) once. The points of all
// groups are one pool of work: a worker takes a point of the earliest
// loaded group that has one left, and the next groups load while the points
// before them run (sweep_schedule.h: how far ahead, within half the memory
// budget), so that no worker waits for a group's longest point or for a
// load. A
// point that fails (a scene not installed, memory exhausted) becomes a
// failed record with its error; the others go on.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

// What a worker did and when (seconds since run_points began): loading a
// group (its scene, when not loaded already, and its traces) or running one
// point. For a timeline of a sweep (bench/sweep-schedule).
struct SweepTask {
  enum class Kind { load, point };
  Kind kind;
  size_t group;  // groups numbered in the order their first point comes
  size_t point;  // the point run, or the group's first point for a load
  unsigned worker;
  double start_s, end_s;
  // A point's memory replay (schemes/memory_tape.h): none (not shared),
  // recorded for points that differ from it only in timing, played back
  // from such a point's recording, or run in full after its calls differed.
  SharedReplay::Use replay = SharedReplay::Use::none;
};

struct SweepRunOptions {
  unsigned jobs = 0;      // points run at once (0: every core)
  bool use_cache = true;  // the trace cache ($OOVR_CACHE_DIR)
  // Points that differ only in timing share one memory replay (the results
  // are the same either way; off only to measure what sharing saves).
  bool share_replays = true;
  std::string command;  // the command line, recorded with every run
  // Called once per point, as it finishes, one call at a time (from worker
  // threads): store or write the record here.
  std::function<void(const RunRecord&)> on_record;
  // What the engine is doing between points ("loading courtyard"), for a
  // progress display; may be empty.
  std::function<void(const std::string&)> on_status;
  // Called once per load and per point, as it ends, one call at a time
  // (with the others above); may be empty.
  std::function<void(const SweepTask&)> on_task;
  // Called with the points whose work starts (a point's run, or a group's
  // load for all its points: `starting`) and with a group's points when
  // its load has ended (not `starting`), by the worker about to do the work,
  // before it; may be empty. Unlike the others, calls may come from several
  // workers at once. A point's work ends with its record.
  std::function<void(const std::vector<size_t>& points, bool starting)> on_flight;
};

// Runs s.points[i] for every i in `which` (resolved: resolve_all).
void run_points(const Sweep& s, const std::vector<size_t>& which, const SweepRunOptions& o);

// Runs them as run_points does and writes each record into `db` as it ends,
// then calls o.on_record with it: the one routine that writes runs, used by
// `oovr sweep`'s workers, `oovr paper` and Python's oovr.sweep. The records
// are written by a thread of their own, several to a transaction, while the
// workers go on (results_writer.h); o.on_record is called from that thread
// once its record is committed, and every callback of `o` one at a time.
// With `track_in_flight`, the database marks the points whose work has
// started with this process, on disk before the work starts (o.on_flight is
// then called after the mark's commit), which the sweep's supervisor reads
// to find a point that killed its worker.
void run_points_into(const Sweep& s, const std::vector<size_t>& which, ResultsDb& db, SweepRunOptions o,
                     bool track_in_flight = false);

// What running a sweep into a database that may hold some of its points
// does: the points to run, and what it keeps.
struct SweepPlan {
  std::vector<size_t> todo;  // points to run, in file order
  size_t held = 0;           // points the database holds and keeps
  size_t retried = 0;        // failed points among `todo`, run again
  // When the database holds this sweep from another version of its file
  // and the plan reconciles them: its runs that the file no longer has
  // (deleted), and those kept whose place in the file moved.
  bool reconciled = false;
  std::vector<std::string> stale;
  std::vector<std::pair<std::string, int>> moved;
  // Runs kept that another build of oovr made (a point's id is its
  // configuration, not the model that ran it): one line per build.
  std::vector<std::string> notes;
};
// Decides what to run. Without `resume` or `retry_failed`, a database that
// holds some of the points is an Error (naming the database and what to
// do), never run into again. `retry_failed` runs the failed points again.
// A database holding a sweep of this name with another definition (an
// edited file, or another sweep of the same name) is an Error naming what
// differs, unless `reconcile`: then the runs the file no longer has are
// deleted and the others kept, at their new places.
SweepPlan plan_sweep(const Sweep& s, const ResultsDb& db, bool resume, bool retry_failed, bool reconcile = false);
// Records the sweep in the database, removes the failed runs the plan
// retries and applies a reconciliation, before any point runs.
void begin_sweep(const Sweep& s, const SweepPlan& plan, ResultsDb& db, const std::string& command);

// The sweeps table's row for `s`, run by `command`.
SweepRecord sweep_record(const Sweep& s, const std::string& command);

// The record of a point that did not run, with its error.
RunRecord failed_record(const Sweep& s, size_t index, const std::string& error, const std::string& command);

}  // namespace oovr
