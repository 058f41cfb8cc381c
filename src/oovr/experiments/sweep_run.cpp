#include "oovr/experiments/sweep_run.h"

#include "oovr/experiments/results_writer.h"

#include <unistd.h>

#include <signal.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <thread>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/host.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/core/parallel.h"
#include "oovr/core/text.h"
#include "oovr/core/version.h"
#include "oovr/experiments/sweep_schedule.h"
#include "oovr/pipeline/image.h"
#include "oovr/run/frames.h"
#include "oovr/run/result_images.h"
#include "oovr/run/result_json.h"
#include "oovr/run/result_metrics.h"
#include "oovr/scene/load.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/memory_tape.h"

namespace oovr {

namespace {

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// What every record of point `index` carries, whatever its outcome.
RunRecord record_of(const Sweep& s, size_t index, const std::string& command) {
  const SweepPoint& p = s.points[index];
  RunRecord r;
  r.id = p.id;
  r.sweep = s.name;
  r.position = int(index);
  r.scene = p.scene;
  r.scheme = p.scheme;
  const StereoRig rig = parse_frame_resolution(p.resolution);
  r.resolution = std::to_string(rig.frame_width()) + "x" + std::to_string(rig.frame_height());
  r.frame = p.frame;
  r.frames = p.window;
  r.aniso = p.aniso;
  // Swept values as numbers in base units where the key has a unit, so
  // that columns sort and plot as numbers.
  const auto entries = scheme_entries(p.scheme, p.machine.entries);
  for (const auto& [key, text] : p.swept) {
    const auto it = entries.find(key);
    r.swept[key] = it != entries.end() ? base_value(it->second) : nlohmann::ordered_json(text);
  }
  r.config = to_json(entries);
  r.oovr_version = version();
  r.git_commit = git_commit();
  r.command = printable(command, true);  // as a record may hold it (results_db.h): no control characters
  r.host = host_name().empty() ? "unknown" : host_name();
  r.started = utc_now();
  return r;
}

// $OOVR_FAULT_POINT=ID:HOW makes the point of id ID die as a defect or
// the kernel would kill it, for the tests of sweep_supervise.h: "segv"
// (a crash), "kill" (the OOM killer: SIGKILL) or "group" (SIGKILL to the
// whole process group, as a cgroup's OOM kill of a job takes every
// process). Only the tests set it.
void inject_fault(const std::string& id) {
  const char* env = std::getenv("OOVR_FAULT_POINT");
  if (!env) return;
  const std::string spec = env;
  if (spec.rfind(id + ":", 0) != 0) return;
  const std::string how = spec.substr(id.size() + 1);
  if (how == "segv") std::raise(SIGSEGV);
  if (how == "kill") std::raise(SIGKILL);
  if (how == "group") ::kill(0, SIGKILL);
}

std::vector<RunImage> images_of(const FrameOutput& first, const SchemeResult& result) {
  std::vector<RunImage> out;
  RunImage gpm;
  gpm.kind = "gpm";
  const Image img = gpm_image(first, result);
  gpm.width = img.width;
  gpm.height = img.height;
  gpm.data = encode_png(img);
  nlohmann::ordered_json legend;
  for (int g = 0; g < result.gpms; ++g) legend["gpm" + std::to_string(g)] = gpm_colour(g);
  gpm.legend = legend.dump();
  out.push_back(std::move(gpm));
  RunImage tiles;
  tiles.kind = "tile_traffic";
  tiles.width = first.trace.tiles_x;
  tiles.height = first.trace.tiles_y;
  tiles.data = nlohmann::json(result.tile_inter_gpm_bytes).dump();
  tiles.legend = nlohmann::json{{"tile_pixels", kTileSize}, {"unit", "B"}}.dump();
  out.push_back(std::move(tiles));
  return out;
}

}  // namespace

SweepRecord sweep_record(const Sweep& s, const std::string& command) {
  SweepRecord r;
  r.name = s.name;
  r.file = s.file;
  r.definition = s.definition;
  r.swept_keys = s.swept_keys;
  r.points = s.points.size();
  r.command = printable(command, true);
  return r;
}

RunRecord failed_record(const Sweep& s, size_t index, const std::string& error, const std::string& command) {
  RunRecord r = record_of(s, index, command);
  r.status = "failed";
  r.error = printable(error, true);  // an error may quote a hostile file
  return r;
}

namespace {

// One group of points over the same traces (trace_group), as the pool holds it.
// Calls `f` when it goes out of scope, however the scope is left.
template <class F>
struct OnExit {
  F f;
  ~OnExit() { f(); }
};

// Points of a group that may share one memory replay (schemes/memory_tape.h):
// the first to run records it, the others play it back.
struct SharedReplaySlot {
  size_t leader = 0;  // the point that records it
  size_t left = 0;    // points that have not finished with it
  std::promise<std::shared_ptr<const MemoryTape>> recorded;
  std::shared_future<std::shared_ptr<const MemoryTape>> tape;  // null: recorded none (the leader failed)
};

struct Group {
  // Sweep indices: the first point of each shared replay first, then the
  // others (so that no point waits for a recording not yet begun), each
  // part in the order given.
  std::vector<size_t> points;
  std::optional<FrameWindow> frames;                           // while loaded and held, unless the load failed
  std::map<size_t, std::shared_ptr<SharedReplaySlot>> shared;  // by sweep index, the points that share
};

// The sweep's points as one pool of work over all groups, handed out as
// SweepSchedule says (sweep_schedule.h): no barrier at a group's end, and
// later groups' scenes and traces load while the points before them run. A
// scene is loaded once and shared by the groups held that use it, and by
// the next group to load. What each point computes does not depend on any of this:
// results are those of one job, whatever the order they finish in.
class PointPool {
 public:
  PointPool(const Sweep& s, const std::vector<size_t>& which, const SweepRunOptions& o, unsigned workers)
      : m_sweep(s),
        m_options(o),
        m_start(std::chrono::steady_clock::now()),
        m_schedule(group_points(s, which, o.share_replays, m_groups), workers, trace_memory_budget()) {}

  void work(unsigned worker) {
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;) {
      if (m_abort) return;
      const SweepSchedule::Action a = m_schedule.next();
      switch (a.kind) {
        case SweepSchedule::Action::Kind::stop: return;
        case SweepSchedule::Action::Kind::wait: m_changed.wait(lock); continue;
        case SweepSchedule::Action::Kind::load: {
          Group& g = m_groups[a.group];
          const std::string& name = scene_of(a.group);
          std::shared_future<std::shared_ptr<const Scene>> scene;
          std::optional<std::promise<std::shared_ptr<const Scene>>> promise;  // when this load loads the scene
          if (const auto it = m_scenes.find(name); it != m_scenes.end()) scene = it->second;
          else {
            promise.emplace();
            scene = m_scenes[name] = promise->get_future().share();
          }
          lock.unlock();
          guarded(lock, [&] { load(a.group, scene, promise ? &*promise : nullptr, worker); });
          m_schedule.loaded(a.group, g.frames.has_value(), g.frames ? window_bytes(*g.frames) : 0);
          if (!g.frames) forget_scenes();
          break;
        }
        case SweepSchedule::Action::Kind::point: {
          Group& g = m_groups[a.group];
          lock.unlock();
          guarded(lock, [&] { run_point(a.group, g.points[a.point], worker); });
          if (m_schedule.point_done(a.group)) {
            g.frames.reset();
            forget_scenes();
          }
          break;
        }
      }
      m_changed.notify_all();
    }
  }

  void rethrow() {
    if (m_error) std::rethrow_exception(m_error);
  }

 private:
  // Groups of the points in `which`, in the order their first point comes;
  // returns their sizes.
  static std::vector<size_t> group_points(const Sweep& s, const std::vector<size_t>& which, bool share,
                                          std::vector<Group>& groups) {
    std::map<std::string, size_t> index;
    for (size_t i : which) {
      const SweepPoint& p = s.points.at(i);
      const auto [it, added] = index.emplace(trace_group(p), groups.size());
      if (added) groups.emplace_back();
      groups[it->second].points.push_back(i);
    }
    if (share)
      for (Group& g : groups) share_replays(s, g);
    std::vector<size_t> sizes;
    for (const Group& g : groups) sizes.push_back(g.points.size());
    return sizes;
  }

  // Finds the points of `g` whose runs may share a memory replay (equal
  // shared_replay_key and window: points that differ only in timing, such
  // as a link bandwidth sweep of the baseline) and puts each key's first
  // point before the others.
  static void share_replays(const Sweep& s, Group& g) {
    std::map<std::string, std::vector<size_t>> by_key;
    std::vector<std::string> keys;
    for (size_t i : g.points) {
      const SweepPoint& p = s.points[i];
      std::string key;
      try {
        key = shared_replay_key(find_scheme(p.scheme), p.machine) + "\nwindow=" + std::to_string(p.window);
      } catch (const Error&) {
        // An unknown scheme: the point fails when it runs, alone.
      }
      keys.push_back(key);
      if (!key.empty()) by_key[key].push_back(i);
    }
    std::vector<size_t> first, rest;
    for (size_t k = 0; k < g.points.size(); ++k) {
      const size_t i = g.points[k];
      const auto it = keys[k].empty() ? by_key.end() : by_key.find(keys[k]);
      if (it == by_key.end() || it->second.size() < 2) {
        first.push_back(i);
        continue;
      }
      if (it->second.front() == i) {
        auto slot = std::make_shared<SharedReplaySlot>();
        slot->leader = i;
        slot->left = it->second.size();
        slot->tape = slot->recorded.get_future().share();
        for (size_t j : it->second) g.shared[j] = slot;
        first.push_back(i);
      } else {
        rest.push_back(i);
      }
    }
    g.points = first;
    g.points.insert(g.points.end(), rest.begin(), rest.end());
  }

  // Runs `f` with the pool's lock released (the caller released it) and
  // takes it again; an exception that is not a point's failure (a callback's,
  // a defect's) stops the pool and is rethrown by run_points.
  template <typename F>
  void guarded(std::unique_lock<std::mutex>& lock, F&& f) {
    try {
      f();
    } catch (...) {
      lock.lock();
      if (!m_error) m_error = std::current_exception();
      m_abort = true;
      m_changed.notify_all();
      return;
    }
    lock.lock();
  }

  const std::string& scene_of(size_t group) const { return m_sweep.points[m_groups[group].points.front()].scene; }

  // Lets loaded scenes go unless a group held, or the last group to start
  // loading (the next may share it), has them.
  void forget_scenes() {
    for (auto it = m_scenes.begin(); it != m_scenes.end();) {
      bool used = scene_of(m_schedule.started() - 1) == it->first;
      for (size_t k = 0; k < m_schedule.started() && !used; ++k) used = m_schedule.held(k) && scene_of(k) == it->first;
      it = used ? std::next(it) : m_scenes.erase(it);
    }
  }

  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }

  void emit(const RunRecord& r) {
    std::lock_guard<std::mutex> lock(m_callback_mutex);
    if (m_options.on_record) m_options.on_record(r);
  }
  void status(const std::string& line) {
    std::lock_guard<std::mutex> lock(m_callback_mutex);
    if (m_options.on_status) m_options.on_status(line);
  }
  void task(const SweepTask& t) {
    std::lock_guard<std::mutex> lock(m_callback_mutex);
    if (m_options.on_task) m_options.on_task(t);
  }
  // Not under the callbacks' lock: it may wait until the points' mark is
  // on disk (run_points_into), which the others need not wait for.
  void flight(const std::vector<size_t>& points, bool starting) {
    if (m_options.on_flight) m_options.on_flight(points, starting);
  }

  // Loads a group's traces, and its scene when `promise` is given (else
  // another load gives it): on failure, every point of the group gets a
  // failed record and the group no traces.
  void load(size_t index, const std::shared_future<std::shared_ptr<const Scene>>& scene,
            std::promise<std::shared_ptr<const Scene>>* promise, unsigned worker) {
    Group& g = m_groups[index];
    const double t0 = seconds();
    const SweepPoint& first = m_sweep.points[g.points.front()];
    int window = 0;
    for (size_t i : g.points) window = std::max(window, m_sweep.points[i].window);
    std::string why;
    flight(g.points, true);
    try {
      if (promise) {
        status("loading " + first.scene);
        try {
          promise->set_value(std::make_shared<const Scene>(load_scene(first.scene)));
        } catch (...) {
          promise->set_exception(std::current_exception());
        }
      }
      const std::shared_ptr<const Scene> loaded = scene.get();
      status("traces of " + first.scene + " at " + first.resolution);
      WindowRequest req;
      req.first = first.frame;
      req.count = window;
      req.aniso = first.aniso;
      req.use_cache = m_options.use_cache;
      req.need_first_image = m_sweep.images;
      g.frames = load_window(loaded, parse_frame_resolution(first.resolution), first.machine, req);
    } catch (const Error& e) {
      why = printable(e.what(), true);
    } catch (const std::bad_alloc&) {
      why = out_of_memory_message("loading " + first.scene + " at " + first.resolution);
    }
    task({SweepTask::Kind::load, index, g.points.front(), worker, t0, seconds()});
    flight(g.points, false);
    if (!why.empty()) {
      g.frames.reset();
      for (size_t i : g.points) emit(failed_record(m_sweep, i, why, m_options.command));
      return;
    }
    status("running " + std::to_string(g.points.size()) + " points on " + first.scene);
  }

  void run_point(size_t index, size_t i, unsigned worker) {
    const SweepPoint& p = m_sweep.points[i];
    const FrameWindow& frames = *m_groups[index].frames;
    RunRecord r = record_of(m_sweep, i, m_options.command);
    const double t0 = seconds();
    flight({i}, true);
    // A shared replay: the leader records it and hands it on however its
    // run ends (a failed one hands on none: the others run in full); the
    // others wait for it, and the last to finish lets it go.
    std::shared_ptr<SharedReplaySlot> slot;
    std::shared_future<std::shared_ptr<const MemoryTape>> tape;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      const auto it = m_groups[index].shared.find(i);
      if (it != m_groups[index].shared.end()) {
        slot = it->second;
        tape = slot->tape;
      }
    }
    SharedReplay share;
    bool handed_on = false;
    const auto hand_on = [&] {
      if (!slot || handed_on) return;
      handed_on = true;
      if (slot->leader == i) slot->recorded.set_value(share.use == SharedReplay::Use::recorded ? share.tape : nullptr);
      std::lock_guard<std::mutex> lock(m_mutex);
      if (--slot->left == 0) slot->tape = {};
    };
    const OnExit<decltype(hand_on)&> guard{hand_on};
    if (slot && slot->leader != i) share.tape = tape.get();
    SharedReplay* shared = slot && (slot->leader == i || share.tape) ? &share : nullptr;
    inject_fault(p.id);
    try {
      const SchemeResult result =
          run_scheme_window(find_scheme(p.scheme), *frames.scene, *frames.frames, p.machine, p.window, nullptr, shared);
      r.status = "done";
      r.result = stored_result_json(result);  // its statistics are its metrics rows
      r.metrics = metrics_of(result);
      if (m_sweep.images && !frames.outputs.empty() && !frames.outputs.front().colour.rgba.empty())
        r.images = images_of(frames.outputs.front(), result);
    } catch (const Error& e) {
      r.status = "failed";
      r.error = printable(e.what(), true);
    } catch (const std::bad_alloc&) {
      r.status = "failed";
      r.error = out_of_memory_message("simulating " + p.scheme + " on " + p.scene);
    }
    hand_on();
    const double t1 = seconds();
    r.wall_s = t1 - t0;
    emit(r);
    task({SweepTask::Kind::point, index, i, worker, t0, t1, share.use});
  }

  const Sweep& m_sweep;
  const SweepRunOptions& m_options;
  const std::chrono::steady_clock::time_point m_start;
  std::vector<Group> m_groups;  // in the order their first point comes
  std::mutex m_mutex;           // guards everything below, and the groups' frames while loads and points change them
  std::condition_variable m_changed;
  SweepSchedule m_schedule;
  std::map<std::string, std::shared_future<std::shared_ptr<const Scene>>> m_scenes;
  bool m_abort = false;
  std::exception_ptr m_error;
  std::mutex m_callback_mutex;  // one callback at a time
};

}  // namespace

void run_points(const Sweep& s, const std::vector<size_t>& which, const SweepRunOptions& o) {
  unsigned workers = o.jobs ? o.jobs : default_thread_count();
  workers = unsigned(std::max<size_t>(1, std::min<size_t>(workers, which.size())));
  PointPool pool(s, which, o, workers);
  std::vector<std::thread> threads;
  threads.reserve(workers - 1);
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back([&pool, w] { pool.work(w); });
  pool.work(0);
  for (auto& t : threads) t.join();
  pool.rethrow();
}

SweepPlan plan_sweep(const Sweep& s, const ResultsDb& db, bool resume, bool retry_failed, bool reconcile) {
  SweepPlan plan;
  const auto definitions = db.sweep_definitions();
  if (const auto d = definitions.find(s.name); d != definitions.end() && d->second != s.definition) {
    std::map<std::string, size_t> index;
    for (size_t i = 0; i < s.points.size(); ++i) index[s.points[i].id] = i;
    size_t kept = 0;
    for (const auto& [id, position] : db.run_positions(s.name)) {
      const auto it = index.find(id);
      if (it == index.end()) plan.stale.push_back(id);
      else {
        ++kept;
        if (size_t(position) != it->second) plan.moved.emplace_back(id, int(it->second));
      }
    }
    if (!reconcile)
      throw Error("the database " + db.path() + " holds a sweep '" + s.name + "' defined otherwise than " + s.file + " (" +
                  std::to_string(kept) + " of its runs are points of this file, " + std::to_string(plan.stale.size()) +
                  " are not): give --reconcile to keep the " + std::to_string(kept) + " and delete the " +
                  std::to_string(plan.stale.size()) + ", or name the sweep otherwise, or use another database");
    plan.reconciled = true;
    plan.notes.push_back("the sweep file differs from the sweep '" + s.name + "' in the database: " + std::to_string(kept) +
                         " runs kept (" + std::to_string(plan.moved.size()) + " moved to their new places), " +
                         std::to_string(plan.stale.size()) + " deleted (points the file no longer has)");
  }
  const auto status = db.run_status();
  for (size_t i = 0; i < s.points.size(); ++i) {
    const auto it = status.find(s.points[i].id);
    if (it == status.end()) plan.todo.push_back(i);
    else if (retry_failed && it->second == "failed") {
      plan.todo.push_back(i);
      ++plan.retried;
    } else ++plan.held;
  }
  if ((plan.held || plan.retried) && !resume && !retry_failed)
    throw Error("the database " + db.path() + " holds " + std::to_string(plan.held) + " of this sweep's " +
                std::to_string(s.points.size()) + " points already: give --resume to run the other " +
                std::to_string(plan.todo.size()) + ", or another --db");
  // Runs kept from another build: say so rather than mix builds silently.
  if (plan.held) {
    const auto commits = db.run_commits();
    std::map<std::string, size_t> other;
    for (const auto& p : s.points) {
      const auto it = commits.find(p.id);
      if (it != commits.end() && it->second != git_commit() && status.at(p.id) == "done") ++other[it->second];
    }
    for (const auto& [commit, n] : other)
      plan.notes.push_back(std::to_string(n) + " of the runs kept were made by oovr " + commit + ", not by this one (" +
                           git_commit() + "); start a new database to have every run from one build");
  }
  return plan;
}

void begin_sweep(const Sweep& s, const SweepPlan& plan, ResultsDb& db, const std::string& command) {
  for (const auto& id : plan.stale) db.remove(id);
  for (const auto& [id, position] : plan.moved) db.set_position(id, position);
  db.add_sweep(sweep_record(s, command), plan.reconciled);
  if (!plan.retried) return;
  const auto status = db.run_status();
  for (size_t i : plan.todo)
    if (status.count(s.points[i].id)) db.remove(s.points[i].id);  // a failed run, retried
}

void run_points_into(const Sweep& s, const std::vector<size_t>& which, ResultsDb& db, SweepRunOptions o, bool track_in_flight) {
  // The caller's callbacks, one at a time: the writer calls on_record's and
  // on_flight's on its thread, the workers the others on theirs.
  const auto serial = std::make_shared<std::mutex>();
  const auto one_at_a_time = [serial](auto f) {
    return f ? decltype(f)([serial, f](const auto&... args) {
      std::lock_guard<std::mutex> lock(*serial);
      f(args...);
    })
             : f;
  };
  o.on_status = one_at_a_time(std::move(o.on_status));
  o.on_task = one_at_a_time(std::move(o.on_task));
  // Many runs: the metrics' index is built once they are written.
  const ResultsDb::Bulk bulk = db.bulk(which.size());
  // Stored first: a callback that throws loses nothing.
  ResultsWriter writer(db, one_at_a_time(std::move(o.on_record)),
                       track_in_flight ? one_at_a_time(std::move(o.on_flight)) : ResultsWriter::Marked{});
  o.on_record = [&writer](const RunRecord& r) { writer.record(r); };
  if (track_in_flight) {
    // A point's work waits until its mark is on disk.
    o.on_flight = [&writer, &s](const std::vector<size_t>& points, bool starting) {
      std::vector<std::string> ids;
      for (size_t i : points) ids.push_back(s.points[i].id);
      writer.mark(std::move(ids), starting ? int64_t(::getpid()) : 0, points, starting, starting);
    };
  } else {
    o.on_flight = one_at_a_time(std::move(o.on_flight));
  }
  run_points(s, which, o);
  writer.finish();
}

}  // namespace oovr
