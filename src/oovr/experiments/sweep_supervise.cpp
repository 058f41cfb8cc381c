#include "oovr/experiments/sweep_supervise.h"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/sweep_run.h"

namespace oovr {

namespace {

// The child being waited for, for the signal handler that passes on an
// interruption.
volatile sig_atomic_t g_child = 0;
volatile sig_atomic_t g_interrupted = 0;

void pass_on(int sig) {
  g_interrupted = sig;
  if (g_child > 0) ::kill(pid_t(g_child), sig);
}

// Installs pass_on for SIGINT, SIGTERM and SIGHUP while it lives.
class PassOn {
 public:
  PassOn() {
    struct sigaction a {};
    a.sa_handler = pass_on;
    sigemptyset(&a.sa_mask);
    for (size_t i = 0; i < 3; ++i) ::sigaction(kSignals[i], &a, &m_old[i]);
  }
  ~PassOn() {
    for (size_t i = 0; i < 3; ++i) ::sigaction(kSignals[i], &m_old[i], nullptr);
  }
  PassOn(const PassOn&) = delete;
  PassOn& operator=(const PassOn&) = delete;

 private:
  static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction m_old[3]{};
};

std::string signal_name(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

}  // namespace

std::string death_reason(int sig) {
  if (sig == SIGKILL)
    return "the process running this point was killed (SIGKILL): the kernel's OOM killer does this when a memory limit is "
           "reached (a cgroup's: a container's, a SLURM job's), as does kill -9";
  return "the process running this point died of " + signal_name(sig) + " (" + strsignal(sig) +
         "): a defect of oovr or of a library it calls; please report it with this point";
}

int supervise_points(const Sweep& s, const std::vector<size_t>& todo, const SuperviseOptions& o) {
  std::map<std::string, size_t> index;
  for (size_t i : todo) index[s.points[i].id] = i;
  const auto record_failed = [&](ResultsDb& db, const std::string& id, const std::string& why) {
    const size_t i = index.at(id);
    db.insert(failed_record(s, i, why, o.command));
    if (o.note)
      o.note("point " + std::to_string(i + 1) + " (" + printable(s.points[i].scene) + ", " + s.points[i].scheme +
             ") recorded as failed: " + why);
  };
  std::set<std::string> alone;  // points to run one at a time first: they were in flight when a process died
  {
    // Marks left by processes that died with their parent (no process of
    // this database runs now: this one holds its lock).
    ResultsDb db(o.db, ResultsDb::Access::write, o.lock);
    for (const InFlight& f : db.in_flight()) {
      if (!index.count(f.id)) continue;
      const int deaths = f.pid != 0 ? f.deaths + 1 : f.deaths;
      if (f.pid != 0) db.add_death(f.id);
      if (deaths >= 2)
        record_failed(db, f.id,
                      "the processes running this point died " + std::to_string(deaths) +
                          " times, each with the sweep itself (killed together: a cgroup's OOM kill can take every "
                          "process of a job, as does kill -9 of the process group)");
      else if (deaths == 1) alone.insert(f.id);
    }
  }
  PassOn pass_on_interrupts;
  for (;;) {
    std::vector<size_t> batch;
    unsigned jobs = o.jobs;
    {
      const ResultsDb db(o.db, ResultsDb::Access::write, o.lock);
      const auto status = db.run_status();
      for (size_t i : todo)
        if (!status.count(s.points[i].id) && (alone.empty() || alone.count(s.points[i].id))) batch.push_back(i);
      if (batch.empty() && !alone.empty()) {
        alone.clear();
        continue;
      }
    }
    if (batch.empty()) return 0;
    if (!alone.empty()) {
      jobs = 1;
      if (o.note) o.note(std::to_string(batch.size()) + " point(s) in flight when a process died: run again one at a time");
    }
    std::fflush(nullptr);
    const pid_t parent = ::getpid();
    const pid_t child = ::fork();
    if (child < 0) throw Error(std::string("cannot start a process for the sweep's points: ") + std::strerror(errno));
    if (child == 0) {
      // The child dies with this process (kill -9 of the sweep stops its
      // points too, their marks left for the next --resume).
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(1);
      // The child: the points, then out without running the parent's
      // exit handlers (its buffers flushed first).
      int code = 0;
      try {
        o.run(batch, jobs);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "oovr: error: %s\n", printable(e.what(), true).c_str());
        code = 1;
      }
      std::fflush(nullptr);
      ::_exit(code);
    }
    g_child = child;
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    g_child = 0;
    if (WIFEXITED(status)) {
      if (WEXITSTATUS(status) != 0) return 1;  // the child said why
      alone.clear();
      if (g_interrupted) return 128 + g_interrupted;
      continue;
    }
    const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : SIGKILL;
    ResultsDb db(o.db, ResultsDb::Access::write, o.lock);
    std::vector<std::string> dead;
    for (const InFlight& f : db.in_flight())
      if (f.pid == child && index.count(f.id)) dead.push_back(f.id);
    if (g_interrupted || sig == SIGINT || sig == SIGTERM || sig == SIGHUP) {
      db.mark_in_flight(dead, 0);  // interrupted: no point to blame
      return 128 + (g_interrupted ? int(g_interrupted) : sig);
    }
    if (dead.empty())
      throw Error("a process running the sweep's points died of " + signal_name(sig) + " while no point was in flight");
    if (dead.size() == 1 || jobs == 1) {
      // Its point (or the points of the group it was loading) killed it.
      for (const auto& id : dead) {
        record_failed(db, id, death_reason(sig));
        alone.erase(id);
      }
    } else {
      for (const auto& id : dead) {
        db.add_death(id);
        alone.insert(id);
      }
    }
  }
}

}  // namespace oovr
