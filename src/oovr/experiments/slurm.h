// The SLURM backend of `oovr sweep` (docs/sweeps.md, "On a SLURM
// cluster"): the points still to run are cut into chunks, one per task of
// an sbatch job array; each task runs its chunk with this oovr and appends
// one JSON record per point to its own file in the job folder (no two
// writers share a file, and nothing writes the database concurrently);
// `oovr sweep --collect` then merges the files into the database. A task
// restarted (requeued, or run again by hand) skips the points its file
// already holds; a line cut short by a lost node is left out and named.
#pragma once

#include <string>
#include <vector>

#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"

namespace oovr {

struct SlurmOptions {
  std::string dir;         // the job folder (created)
  std::string partition;   // "" : the cluster's default
  std::string time_limit;  // per task, as sbatch takes it ("30", "2:00:00"); "": the partition's
  int array_limit = 0;     // tasks running at once (the array's %N); 0: no limit
  int chunk = 0;           // points per task, in sweep order; 0: a task per trace group (slurm_tasks)
  int cpus_per_task = 1;   // each task runs this many points at once
  bool use_cache = true;
  bool wait = false;                     // sbatch --wait: return when every task has ended
  std::string executable;                // the oovr the tasks run (default: this one)
  std::vector<std::string> sbatch_args;  // passed to sbatch as they are
};

struct SlurmSubmission {
  std::string job_id;
  int tasks = 0;
  size_t points = 0;
  std::string script;     // the sbatch script's path
  int sbatch_status = 0;  // sbatch's exit status (with wait: non-zero when a task failed)
  std::string sbatch_output;
};

// The most tasks a job array is cut into by default.
inline constexpr size_t kMaxTasks = 1000;

// The points of `todo` (places in s.points) each array task runs. With
// `chunk` > 0, `chunk` consecutive points a task. Otherwise (0) a task per
// trace group (trace_group: the points replaying the same traces), so that
// a task renders or reads each trace once and no two tasks render the same;
// past kMaxTasks groups, consecutive groups share a task.
std::vector<std::vector<size_t>> slurm_tasks(const Sweep& s, const std::vector<size_t>& todo, int chunk);

// Checks what can be checked here of what the nodes need before anything
// is written: the game data the sweep's scenes read (scene_data_missing).
// Missing here, it is most likely missing there too, and every point of
// those scenes would fail on the nodes: Error naming each scene and where
// its data was looked for.
void check_slurm_scenes(const Sweep& s);
// The oovr the tasks will run (`exe`, this one by default): an absolute
// path to an executable file that is still there. Error otherwise. That the
// nodes see it at the same path job.sbatch checks on each node, first.
void check_slurm_executable(const std::string& exe);
// This process's executable, by /proc/self/exe.
std::string this_executable();

// Writes the job folder (a copy of the sweep file, the manifest of each
// task's points, the sbatch script) and submits it with sbatch. Throws
// Error when sbatch is missing or refuses the job (with its message).
SlurmSubmission submit_slurm(const Sweep& s, const std::string& sweep_path, const std::vector<size_t>& todo,
                             const std::string& command, const SlurmOptions& o);

// What one array task runs: task `task` of the job folder `dir`, its
// points `jobs` at a time.
void run_slurm_task(const std::string& dir, int task, unsigned jobs);

struct CollectReport {
  size_t files = 0;
  size_t added = 0;                   // runs new to the database
  size_t already = 0;                 // runs the database had
  std::vector<std::string> problems;  // damaged lines, tasks that wrote nothing
};

// Merges every task's records in `dir` into `db`.
CollectReport collect_slurm(const std::string& dir, ResultsDb& db);

// The job submitted from `dir` (its id, which submit_slurm keeps in the
// folder) and how many of its array tasks SLURM still has queued or
// running (squeue). `known` is false when that cannot be told: no job id in
// the folder (a folder of an older oovr, or written by hand), or squeue
// missing or failing.
struct SlurmJobState {
  bool known = false;
  std::string job_id;
  size_t tasks_left = 0;
};
SlurmJobState slurm_job_state(const std::string& dir);

}  // namespace oovr
