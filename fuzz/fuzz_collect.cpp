// libFuzzer target: `oovr sweep --collect` on a SLURM job folder whose task
// file is the input (what a task, a lost node or a forger wrote). The job
// is a real one (kCollectSweep, resolved, its manifest written as
// submit_slurm writes it); each input is task 0's file, collected into a
// database. Whatever the lines, the collect must end (an Error only for the
// database itself), and every run it stored must be one of the job's
// points, whole: the database verifies, each stored id is one the task was
// given. Seeds: oovr-fuzz-seeds writes the task's real lines.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "collect_job.h"
#include "oovr/core/error.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/slurm.h"
#include "oovr/experiments/sweep.h"

namespace fs = std::filesystem;

namespace {

struct Job {
  fs::path dir;
  std::set<std::string> ids;
  Job() {
    dir = fs::temp_directory_path() / ("oovr-fuzz-collect-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    oovr::Sweep s = oovr::parse_sweep(kCollectSweep, "c.toml", "");
    oovr::resolve_all(s);
    nlohmann::json tasks = nlohmann::json::array({nlohmann::json::array()});
    for (size_t i = 0; i < s.points.size(); ++i) {
      tasks[0].push_back({i, s.points[i].id});
      ids.insert(s.points[i].id);
    }
    nlohmann::json m = {{"schema", "oovr.slurm-sweep"},
                        {"sweep", s.name},
                        {"sweep_file", "/c.toml"},
                        {"base_dir", "/"},
                        {"swept_keys", s.swept_keys},
                        {"points", s.points.size()},
                        {"command", "oovr sweep c.toml"},
                        {"use_cache", false},
                        {"tasks", tasks}};
    std::ofstream(dir / "manifest.json") << m.dump(1) << "\n";
    std::ofstream(dir / "sweep.toml") << kCollectSweep;
  }
  ~Job() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Job job;
  std::ofstream(job.dir / "task-0.jsonl", std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  const std::string db_path = (job.dir / "r.db").string();
  fs::remove(db_path);
  oovr::ResultsDb db(db_path);
  (void)oovr::collect_slurm(job.dir.string(), db);  // bad lines are named and left out, never thrown
  db.verify();                                      // what it stored is whole
  for (const auto& [id, status] : db.run_status())
    if (!job.ids.count(id)) __builtin_trap();  // a run the task was not given
  return 0;
}
