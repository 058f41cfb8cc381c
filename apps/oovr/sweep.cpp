// oovr sweep: runs a sweep file's points into a results database, here or
// on a SLURM cluster, with a progress display (docs/sweeps.md).
#include <fmt/core.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/slurm.h"
#include "oovr/experiments/sweep.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/experiments/sweep_supervise.h"
#include "progress.h"

namespace oovr::cli {
namespace {

namespace fs = std::filesystem;

std::string default_db(const SweepArgs& a) {
  if (!a.db.empty()) return a.db;
  return fs::path(a.file).stem().string() + ".db";
}

int print_collect(const CollectReport& rep, const std::string& db_path, const Sweep* s, ResultsDb& db,
                  const std::string& slurm_dir) {
  for (const auto& p : rep.problems) fmt::print("  note: {}\n", printable(p));
  fmt::print("collected {} runs from {} task files into {} ({} there already)\n", rep.added, rep.files, db_path, rep.already);
  if (s) {
    const auto status = db.run_status();
    size_t missing = 0, failed = 0;
    for (const auto& p : s->points) {
      const auto it = status.find(p.id);
      if (it == status.end()) ++missing;
      else if (it->second == "failed") ++failed;
    }
    // Points missing while the job still has tasks queued or running are
    // coming: --resume now would run them here as well.
    std::string rest;
    if (missing) {
      const SlurmJobState job = slurm_job_state(slurm_dir);
      rest = job.known && job.tasks_left
                 ? fmt::format(
                       "; job {} still has {} task{} queued or running (squeue -j {}): collect again once it has "
                       "ended, and only then run what is still missing with --resume",
                       job.job_id, job.tasks_left, job.tasks_left == 1 ? "" : "s", job.job_id)
                 : "; run the sweep again with --resume for the rest (with --backend slurm to submit them again, once "
                   "the notes above are seen to)";
    }
    fmt::print("sweep '{}': {} of {} points in the database, {} of them failed{}\n", s->name, s->points.size() - missing,
               s->points.size(), failed, rest);
    if (missing || failed) return 1;
  }
  return 0;
}

}  // namespace

int sweep(const SweepArgs& a) {
  if (a.task >= 0) {
    if (a.slurm_dir.empty()) throw Error("--task needs --slurm-dir (the job folder)");
    run_slurm_task(a.slurm_dir, a.task, a.jobs);
    return 0;
  }
  if (a.file.empty()) throw Error("give the sweep file: oovr sweep FILE.toml");
  if (a.backend != "local" && a.backend != "slurm") throw Error("--backend " + a.backend + ": use local or slurm");
  Sweep s = read_sweep(a.file, a.settings);
  resolve_all(s);
  if (!s.shared.empty())
    fmt::print("note: {} {} the same run as an earlier point, run once and shared (the first: {})\n", s.shared.size(),
               s.shared.size() == 1 ? "point is" : "points are", printable(s.shared.front()));
  if (a.list) {
    for (size_t i = 0; i < s.points.size(); ++i) {
      const SweepPoint& p = s.points[i];
      std::string settings;
      for (const auto& [k, v] : p.settings) settings += " " + k + "=" + v;
      fmt::print("{:>5} {} {} {} {} frames {}-{}{}\n", i + 1, p.id, p.scene, p.scheme, p.resolution, p.frame,
                 p.frame + p.window - 1, settings);
    }
    fmt::print("sweep '{}': {} points\n", s.name, s.points.size());
    return 0;
  }
  if (a.backend == "slurm" && !a.collect) {  // before the database or the job folder is made
    check_slurm_scenes(s);
    check_slurm_executable(this_executable());
  }
  const std::string db_path = default_db(a);
  const std::string slurm_dir = a.slurm_dir.empty() ? db_path + ".slurm" : a.slurm_dir;
  const DatabaseLock lock(db_path);  // the one writer, until this command ends (its children share it)
  auto db = std::make_unique<ResultsDb>(db_path, ResultsDb::Access::write, &lock);
  db->verify();  // whole, before anything is added to it or kept
  if (a.collect) return print_collect(collect_slurm(slurm_dir, *db), db_path, &s, *db, slurm_dir);

  const SweepPlan plan = plan_sweep(s, *db, a.resume, a.retry_failed, a.reconcile);
  for (const auto& n : plan.notes) fmt::print("note: {}\n", printable(n));
  begin_sweep(s, plan, *db, a.command);
  const std::vector<size_t>& todo = plan.todo;
  const size_t held = plan.held;

  if (a.backend == "slurm") {
    SlurmOptions o;
    o.dir = slurm_dir;
    o.partition = a.partition;
    o.time_limit = a.time_limit;
    o.array_limit = a.array_limit;
    o.chunk = a.chunk;
    o.cpus_per_task = a.cpus_per_task;
    o.use_cache = !a.no_cache;
    o.wait = a.wait;
    o.sbatch_args = a.sbatch_args;
    const SlurmSubmission sub = submit_slurm(s, a.file, todo, a.command, o);
    fmt::print("sweep '{}': submitted job {}: {} points in {} tasks ({}); results in {}\n", s.name, sub.job_id, sub.points,
               sub.tasks, sub.script, slurm_dir);
    if (!a.wait) {
      fmt::print("when it has ended: oovr sweep {} --collect --db {}{}\n", a.file, db_path,
                 a.slurm_dir.empty() ? "" : " --slurm-dir " + a.slurm_dir);
      return 0;
    }
    if (sub.sbatch_status != 0) fmt::print("  note: sbatch --wait ended with status {}: a task failed\n", sub.sbatch_status);
    return print_collect(collect_slurm(slurm_dir, *db), db_path, &s, *db, slurm_dir);
  }

  fmt::print("sweep '{}': {} points{}; results in {}\n", s.name, s.points.size(),
             held ? fmt::format(" ({} in the database already, {} to run)", held, todo.size()) : "", db_path);
  std::fflush(stdout);
  // The points run in child processes (sweep_supervise.h), which open the
  // database themselves: this process closes it first.
  db.reset();
  const auto t0 = std::chrono::steady_clock::now();
  SuperviseOptions so;
  so.db = db_path;
  so.lock = &lock;
  so.jobs = a.jobs;
  so.command = a.command;
  so.note = [](const std::string& line) { fmt::print(stderr, "  note: {}\n", line); };
  so.run = [&](const std::vector<size_t>& which, unsigned jobs) {
    ResultsDb child_db(db_path, ResultsDb::Access::write, &lock);
    Progress progress(which.size());
    SweepRunOptions o;
    o.jobs = jobs;
    o.use_cache = !a.no_cache;
    o.command = a.command;
    o.on_status = [&](const std::string& line) { progress.status(line); };
    o.on_record = [&](const RunRecord& r) { progress.point(r); };
    run_points_into(s, which, child_db, o, true);
    progress.finish();
  };
  const int rc = supervise_points(s, todo, so);
  if (rc != 0) return rc;
  const ResultsDb after(db_path, ResultsDb::Access::read_only);
  const auto status = after.run_status();
  size_t done = 0, failed = 0;
  for (size_t i : todo) {
    const auto it = status.find(s.points[i].id);
    if (it == status.end()) continue;
    ++(it->second == "done" ? done : failed);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fmt::print("sweep '{}': {} points run in {}: {} done, {} failed; {} of {} in {}\n", s.name, todo.size(), clock_time(seconds),
             done, failed, held + done + failed, s.points.size(), db_path);
  if (failed) {
    fmt::print(stderr, "oovr: error: {} of the sweep's points failed (their errors are in the runs table)\n", failed);
    return 1;
  }
  return 0;
}

}  // namespace oovr::cli
