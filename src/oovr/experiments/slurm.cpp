#include "oovr/experiments/slurm.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/host.h"
#include "oovr/core/text.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/run/result_json.h"
#include "oovr/scene/load.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

constexpr const char* kManifestSchema = "oovr.slurm-sweep";
// Records are single lines of a few KB (tens with images): anything
// longer than this is not one of ours.
constexpr uint64_t kMaxResultsFile = uint64_t(1) << 34;

std::string task_file(const std::string& dir, int task) {
  return (fs::path(dir) / ("task-" + std::to_string(task) + ".jsonl")).string();
}

}  // namespace

std::string this_executable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find this oovr's path (/proc/self/exe): " + ec.message());
  return p.string();
}

namespace {

// The last line of a task's log with text on it, printable and at most 300
// characters: what a task that wrote no results said (the node's check of
// the executable below, the loader's missing library, a crash). Empty when
// there is no log.
std::string last_log_line(const std::string& path) {
  const FileRead f = read_regular_file(path, uint64_t(1) << 20, true);
  if (f.failure != FileRead::Failure::none) return "";
  size_t end = f.bytes.find_last_not_of(" \n\r\t");
  if (end == std::string::npos) return "";
  const size_t begin = f.bytes.rfind('\n', end);
  std::string line =
      f.bytes.substr(begin == std::string::npos ? 0 : begin + 1, end + 1 - (begin == std::string::npos ? 0 : begin + 1));
  if (line.size() > 300) line = line.substr(0, 300) + "...";
  return printable(line);
}

nlohmann::json read_manifest(const std::string& dir) {
  const std::string path = (fs::path(dir) / "manifest.json").string();
  const std::string text = read_input_file(path, "SLURM job manifest", uint64_t(1) << 30);
  nlohmann::json m;
  try {
    m = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error("the SLURM job manifest '" + path + "' is not JSON: " + e.what());
  }
  if (!m.is_object() || m.value("schema", "") != kManifestSchema || !m.contains("tasks") || !m["tasks"].is_array())
    throw Error("'" + path + "' is not an oovr SLURM job manifest");
  // Read back, so checked: what oovr wrote, every field of its type.
  const auto bad = [&](const std::string& what) { throw Error("the SLURM job manifest '" + path + "' is damaged: " + what); };
  try {
    if (!is_sweep_name(m.at("sweep").get<std::string>())) bad("its sweep name is not one oovr gives");
    (void)m.at("sweep_file").get<std::string>();
    (void)m.at("base_dir").get<std::string>();
    (void)m.at("command").get<std::string>();
    for (const auto& k : m.at("swept_keys")) (void)k.get<std::string>();
    const int64_t points = json_whole(m.at("points"), 1, int64_t(kMaxPoints), "points");
    std::set<std::string> ids;
    for (const auto& task : m["tasks"]) {
      if (!task.is_array() || task.empty()) bad("a task without points");
      for (const auto& entry : task) {
        if (!entry.is_array() || entry.size() != 2) bad("a task entry that is not [index, id]");
        (void)json_whole(entry[0], 0, points - 1, "a point's index");
        if (!entry[1].is_string() || !is_run_id(entry[1].get<std::string>())) bad("a point id that is not oovr's");
        if (!ids.insert(entry[1].get<std::string>()).second) bad("a point in two tasks");
      }
    }
  } catch (const nlohmann::json::exception& e) {
    bad(e.what());
  } catch (const Error& e) {
    bad(e.what());
  }
  return m;
}

// The sweep as the job was submitted: the copy in the folder, read as if
// it were at its original path (its preset path is relative to that).
Sweep submitted_sweep(const std::string& dir, const nlohmann::json& m) {
  const std::string copy = (fs::path(dir) / "sweep.toml").string();
  const std::string text = read_input_file(copy, "sweep", uint64_t(1) << 20);
  Sweep s = parse_sweep(text, m.at("sweep_file").get<std::string>(), m.at("base_dir").get<std::string>());
  resolve_all(s);
  return s;
}

}  // namespace

std::vector<std::vector<size_t>> slurm_tasks(const Sweep& s, const std::vector<size_t>& todo, int chunk) {
  std::vector<std::vector<size_t>> tasks;
  if (chunk > 0) {
    for (size_t k = 0; k < todo.size(); k += size_t(chunk))
      tasks.emplace_back(todo.begin() + std::ptrdiff_t(k),
                         todo.begin() + std::ptrdiff_t(std::min(todo.size(), k + size_t(chunk))));
    return tasks;
  }
  // The trace groups, in the order their first points come.
  std::vector<std::vector<size_t>> groups;
  std::map<std::string, size_t> index;
  for (size_t i : todo) {
    const auto [it, added] = index.emplace(trace_group(s.points[i]), groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  // At most kMaxTasks tasks: consecutive groups share one when there are more.
  const size_t per = (groups.size() + kMaxTasks - 1) / kMaxTasks;
  for (size_t g = 0; g < groups.size(); g += per) {
    tasks.emplace_back();
    for (size_t k = g; k < std::min(groups.size(), g + per); ++k)
      tasks.back().insert(tasks.back().end(), groups[k].begin(), groups[k].end());
  }
  return tasks;
}

void check_slurm_executable(const std::string& exe) {
  // What can be checked here of the oovr the nodes will run: that it is a
  // program, at an absolute path, and still the file this path names (a
  // build replaced while this process ran leaves "/proc/self/exe" naming
  // "... (deleted)"). Whether the nodes see the same path, only they can
  // say: job.sbatch checks it first on each.
  const fs::path p(exe);
  if (!p.is_absolute()) throw Error("the oovr the nodes would run, '" + printable(exe) + "', is not an absolute path");
  std::error_code ec;
  const auto st = fs::status(p, ec);
  if (ec || !fs::is_regular_file(st))
    throw Error("the oovr the nodes would run, '" + printable(exe) +
                "', is not a file here (was it rebuilt or removed while this one ran?): run oovr sweep again with the "
                "current build");
  if ((st.permissions() & fs::perms::owner_exec) == fs::perms::none)
    throw Error("the oovr the nodes would run, '" + printable(exe) + "', is not executable");
}

void check_slurm_scenes(const Sweep& s) {
  // What can be checked here of what the nodes need: the game data the
  // points' scenes read. Missing here, it is most likely missing there, and
  // every point of those scenes would fail on the nodes.
  std::set<std::string> scenes, missing;
  for (const auto& p : s.points) scenes.insert(p.scene);
  for (const auto& scene : scenes)
    if (const std::string why = scene_data_missing(scene); !why.empty()) missing.insert(printable(scene) + ": " + why);
  if (!missing.empty()) {
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : "; ") + m;
    throw Error("the sweep's scenes need data that is not here, so the nodes would fail their points: " + list +
                ". Install it where the nodes see it too, and point OOVR_OPENARENA_DIR, OOVR_NEXUIZ_DIR, OOVR_TORCS_DIR or "
                "OOVR_CAPTURE_DIR "
                "at it if it is not in its default place (the tasks get this environment; docs/sweeps.md, \"What a node "
                "needs\")");
  }
}

SlurmSubmission submit_slurm(const Sweep& s, const std::string& sweep_path, const std::vector<size_t>& todo,
                             const std::string& command, const SlurmOptions& o) {
  if (todo.empty()) throw Error("nothing to submit: every point is in the database");
  std::error_code ec;
  fs::create_directories(o.dir, ec);
  if (ec) throw Error("cannot create the SLURM job folder '" + o.dir + "': " + ec.message());
  const fs::path dir = fs::absolute(o.dir).lexically_normal();
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".jsonl")
      throw Error("the SLURM job folder '" + o.dir + "' holds results of an earlier job (" + e.path().filename().string() +
                  "): collect them with --collect, then remove the folder or give another --slurm-dir");
  const std::vector<std::vector<size_t>> task_points = slurm_tasks(s, todo, o.chunk);
  const int tasks = int(task_points.size());

  nlohmann::json m;
  m["schema"] = kManifestSchema;
  m["sweep"] = s.name;
  m["sweep_file"] = fs::absolute(sweep_path).lexically_normal().string();
  m["base_dir"] = fs::absolute(sweep_path).parent_path().lexically_normal().string();
  m["swept_keys"] = s.swept_keys;
  m["points"] = s.points.size();
  m["command"] = command;
  m["use_cache"] = o.use_cache;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& chunk : task_points) {
    nlohmann::json points = nlohmann::json::array();
    for (size_t i : chunk) points.push_back({i, s.points[i].id});
    list.push_back(points);
  }
  m["tasks"] = list;
  write_output_file((dir / "sweep.toml").string(), s.definition, "sweep copy");
  write_output_file((dir / "manifest.json").string(), m.dump(1) + "\n", "SLURM job manifest");

  const std::string exe = o.executable.empty() ? this_executable() : o.executable;
  check_slurm_executable(exe);  // checked before the database was made too; it may have gone since
  // sbatch reads the #SBATCH lines and sh the rest: nothing written into
  // them may hold a control character (a new line would start a command),
  // and every word is quoted.
  for (const auto& [what, text] : {std::pair<const char*, std::string>{"the sweep's name", s.name},
                                   {"the job folder", dir.string()},
                                   {"the oovr executable's path", exe},
                                   {"--partition", o.partition},
                                   {"--time", o.time_limit}})
    if (has_control_characters(text)) throw Error(std::string(what) + " '" + printable(text) + "' holds control characters");
  std::string script = "#!/bin/sh\n";
  script += "# oovr sweep '" + s.name + "': " + std::to_string(todo.size()) + " points in " + std::to_string(tasks) +
            " tasks, written by: " + printable(command) + "\n";
  const auto quote = [](const std::string& w) {
    const char* argv[] = {w.c_str()};
    return shell_command_line(1, argv);
  };
  script += "#SBATCH --job-name=" + quote("oovr-" + s.name) + "\n";
  script +=
      "#SBATCH --array=0-" + std::to_string(tasks - 1) + (o.array_limit > 0 ? "%" + std::to_string(o.array_limit) : "") + "\n";
  script += "#SBATCH --output=" + quote((dir / "task-%a.log").string()) + "\n";
  script += "#SBATCH --cpus-per-task=" + std::to_string(o.cpus_per_task) + "\n";
  if (!o.partition.empty()) script += "#SBATCH --partition=" + quote(o.partition) + "\n";
  if (!o.time_limit.empty()) script += "#SBATCH --time=" + quote(o.time_limit) + "\n";
  // On the node, first: is this oovr there? A node without it (a build
  // folder not on a shared file system) says so in the task's log, which
  // --collect shows, rather than sh's bare "not found".
  script += "if [ ! -x " + quote(exe) + " ]; then printf 'oovr: node %s has no executable %s: the nodes need this oovr at " +
            "the same path (docs/sweeps.md, What a node needs)\\n' \"${SLURMD_NODENAME:-$(hostname)}\" " + quote(exe) +
            " >&2; exit 2; fi\n";
  script += "exec " + quote(exe) + " sweep --task \"$SLURM_ARRAY_TASK_ID\" --slurm-dir " + quote(dir.string()) + " --jobs " +
            std::to_string(o.cpus_per_task) + "\n";
  const std::string script_path = (dir / "job.sbatch").string();
  write_output_file(script_path, script, "sbatch script");

  std::vector<std::string> words = {"sbatch", "--parsable"};
  if (o.wait) words.push_back("--wait");
  words.insert(words.end(), o.sbatch_args.begin(), o.sbatch_args.end());
  words.push_back(script_path);
  SlurmSubmission sub;
  sub.tasks = tasks;
  sub.points = todo.size();
  sub.script = script_path;
  sub.sbatch_status = run_command(words, sub.sbatch_output);
  // --parsable prints "jobid[;cluster]" first; with --wait, later lines
  // may say how the job ended.
  const std::string first = sub.sbatch_output.substr(0, sub.sbatch_output.find('\n'));
  sub.job_id = first.substr(0, first.find(';'));
  const bool numeric = !sub.job_id.empty() && std::all_of(sub.job_id.begin(), sub.job_id.end(), ::isdigit);
  if (!numeric) {
    std::string out = sub.sbatch_output;
    while (!out.empty() && out.back() == '\n') out.pop_back();
    if (sub.sbatch_status == 127 || out.find("not found") != std::string::npos)
      throw Error("sbatch is not installed here (SLURM's client commands; scripts/install-deps.sh --services): " + out);
    throw Error("sbatch refused the job " + script_path + " (exit status " + std::to_string(sub.sbatch_status) + "): " + out);
  }
  // Kept, so that a --collect before the job has ended can say what is left.
  write_output_file((dir / "job-id").string(), sub.job_id + "\n", "SLURM job id");
  return sub;
}

SlurmJobState slurm_job_state(const std::string& dir) {
  SlurmJobState st;
  const FileRead f = read_regular_file((fs::path(dir) / "job-id").string(), 64, false);
  if (f.failure != FileRead::Failure::none) return st;
  std::string id = f.bytes;
  while (!id.empty() && id.back() == '\n') id.pop_back();
  if (id.empty() || id.size() > 20 || !std::all_of(id.begin(), id.end(), ::isdigit)) return st;  // not ours: unknown
  st.job_id = id;
  // One line per array task (-r), pending or running, none once it has ended.
  std::string out;
  if (run_command({"squeue", "-h", "-r", "-j", id, "-o", "%i"}, out) != 0) {
    // squeue refuses a job id it has forgotten (ended a while ago): none left.
    st.known = out.find("Invalid job id") != std::string::npos;
    return st;
  }
  st.known = true;
  for (const std::string& line : split_fields(out, '\n'))
    if (line.rfind(id, 0) == 0) ++st.tasks_left;
  return st;
}

void run_slurm_task(const std::string& dir, int task, unsigned jobs) {
  const nlohmann::json m = read_manifest(dir);
  if (task < 0 || size_t(task) >= m["tasks"].size())
    throw Error("task " + std::to_string(task) + " is not one of the job's " + std::to_string(m["tasks"].size()) + " tasks");
  const Sweep s = submitted_sweep(dir, m);
  std::vector<size_t> which;
  for (const auto& entry : m["tasks"][size_t(task)]) {
    const size_t index = size_t(json_whole(entry.at(0), 0, int64_t(kMaxPoints), "a point's index"));
    const std::string id = entry.at(1).get<std::string>();
    if (index >= s.points.size() || s.points[index].id != id)
      throw Error("point " + std::to_string(index + 1) + " of the sweep is not the one submitted (id " + id +
                  "): this oovr resolves the sweep differently from the one that submitted it");
    which.push_back(index);
  }
  // A restarted task keeps what its file holds: whole lines only.
  const std::string path = task_file(dir, task);
  std::set<std::string> have;
  // The task's own file, never a link's target (a link planted in the job
  // folder would have this task rewrite another file).
  const FileRead old = read_regular_file(path, kMaxResultsFile, false);
  if (old.failure == FileRead::Failure::none) {
    const size_t end = old.bytes.rfind('\n');
    const size_t keep = end == std::string::npos ? 0 : end + 1;
    if (keep < old.bytes.size() && truncate(path.c_str(), off_t(keep)) != 0)
      throw Error("cannot cut the damaged last line of '" + path + "': " + std::strerror(errno));
    size_t from = 0;
    while (from < keep) {
      const size_t nl = old.bytes.find('\n', from);
      try {
        have.insert(nlohmann::json::parse(old.bytes.substr(from, nl - from)).at("id").get<std::string>());
      } catch (const nlohmann::json::exception&) {
      }
      from = nl + 1;
    }
  } else if (old.failure != FileRead::Failure::missing) {
    throw Error("cannot read '" + path + "': " + old.why);
  }
  which.erase(std::remove_if(which.begin(), which.end(), [&](size_t i) { return have.count(s.points[i].id) != 0; }), which.end());
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
  SweepRunOptions o;
  o.jobs = jobs;
  o.use_cache = m.value("use_cache", true);
  o.command = m.at("command").get<std::string>();
  o.on_record = [&](const RunRecord& r) {
    const std::string line = to_json(r).dump() + "\n";
    size_t done = 0;
    while (done < line.size()) {
      const ssize_t n = ::write(fd, line.data() + done, line.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
      done += size_t(n);
    }
    if (::fsync(fd) != 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    std::printf("%s %s: %s, %s, %s%s\n", r.status.c_str(), r.id.c_str(), printable(r.scene).c_str(), printable(r.scheme).c_str(),
                r.resolution.c_str(), r.error.empty() ? "" : (": " + printable(r.error)).c_str());
    std::fflush(stdout);
  };
  try {
    run_points(s, which, o);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
}

CollectReport collect_slurm(const std::string& dir, ResultsDb& db) {
  const nlohmann::json m = read_manifest(dir);
  SweepRecord sw;
  sw.name = m.at("sweep").get<std::string>();
  sw.file = m.at("sweep_file").get<std::string>();
  sw.definition = read_input_file((fs::path(dir) / "sweep.toml").string(), "sweep", uint64_t(1) << 20);
  sw.swept_keys = m.at("swept_keys").get<std::vector<std::string>>();
  sw.points = m.at("points").get<size_t>();
  sw.command = m.at("command").get<std::string>();
  db.add_sweep(sw);
  CollectReport rep;
  for (size_t t = 0; t < m["tasks"].size(); ++t) {
    // What this task was given: id -> the point's place in the sweep.
    std::map<std::string, int> given;
    for (const auto& entry : m["tasks"][t]) given[entry[1].get<std::string>()] = entry[0].get<int>();
    const std::string path = task_file(dir, int(t));
    const FileRead f = read_regular_file(path, kMaxResultsFile, false);
    if (f.failure == FileRead::Failure::missing) {
      const std::string said = last_log_line((fs::path(dir) / ("task-" + std::to_string(t) + ".log")).string());
      rep.problems.push_back("task " + std::to_string(t) + " wrote nothing (" + path + " is missing)" +
                             (said.empty() ? "" : "; its log ends: " + said));
      continue;
    }
    if (f.failure != FileRead::Failure::none) {
      rep.problems.push_back("cannot read '" + path + "' (" + f.why + "): its runs are left out");
      continue;
    }
    ++rep.files;
    size_t from = 0, line = 0;
    std::set<std::string> seen;
    while (from < f.bytes.size()) {
      size_t nl = f.bytes.find('\n', from);
      ++line;
      const std::string where = path + " line " + std::to_string(line);
      if (nl == std::string::npos) {
        rep.problems.push_back(where + " is cut short (the task was stopped while writing it): left out");
        break;
      }
      // Each record is checked, and against what the task was given; one
      // that is not right is named and left out, and the others go in.
      RunRecord r;
      std::string why;
      try {
        r = run_record_from_json(nlohmann::ordered_json::parse(f.bytes.substr(from, nl - from)));
        const auto g = given.find(r.id);
        if (g == given.end()) throw Error("run " + r.id + " is not a point this task was given");
        if (r.sweep != sw.name) throw Error("run " + r.id + " belongs to the sweep '" + r.sweep + "'");
        if (r.position != g->second)
          throw Error("run " + r.id + " says it is point " + std::to_string(r.position + 1) + " of the sweep, not " +
                      std::to_string(g->second + 1));
        if (!seen.insert(r.id).second) throw Error("run " + r.id + " is given twice");
      } catch (const std::exception& e) {
        why = e.what();
      }
      from = nl + 1;
      if (!why.empty()) {
        rep.problems.push_back(where + " is not a run of this job (" + why + "): left out");
        continue;
      }
      if (db.insert(r)) ++rep.added;  // a failure to write is the collect's error
      else ++rep.already;
    }
  }
  return rep;
}

}  // namespace oovr
