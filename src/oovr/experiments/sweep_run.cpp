#include "oovr/experiments/sweep_run.h"

#include <chrono>
#include <ctime>
#include <map>
#include <mutex>
#include <new>
#include <optional>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/host.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/core/parallel.h"
#include "oovr/core/version.h"
#include "oovr/experiments/frames.h"
#include "oovr/experiments/result_images.h"
#include "oovr/experiments/result_json.h"
#include "oovr/experiments/result_metrics.h"
#include "oovr/pipeline/image.h"
#include "oovr/scene/load.h"
#include "oovr/scene/stereo.h"

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
  const auto& entries = p.config.entries();
  for (const auto& [key, text] : p.swept) {
    const auto it = entries.find(key);
    r.swept[key] = it != entries.end() ? base_value(it->second) : nlohmann::ordered_json(text);
  }
  r.config = to_json(entries);
  r.oovr_version = version();
  r.git_commit = git_commit();
  r.command = command;
  r.host = host_name().empty() ? "unknown" : host_name();
  r.started = utc_now();
  return r;
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
  r.command = command;
  return r;
}

RunRecord failed_record(const Sweep& s, size_t index, const std::string& error, const std::string& command) {
  RunRecord r = record_of(s, index, command);
  r.status = "failed";
  r.error = error;
  return r;
}

void run_points(const Sweep& s, const std::vector<size_t>& which, const SweepRunOptions& o) {
  std::mutex record_mutex;
  const auto emit = [&](const RunRecord& r) {
    std::lock_guard<std::mutex> lock(record_mutex);
    if (o.on_record) o.on_record(r);
  };
  const auto status = [&](const std::string& line) {
    if (o.on_status) o.on_status(line);
  };
  // Groups of points over the same traces, in the order they first appear.
  std::vector<std::string> order;
  std::map<std::string, std::vector<size_t>> groups;
  for (size_t i : which) {
    const std::string g = trace_group(s.points.at(i));
    if (!groups.count(g)) order.push_back(g);
    groups[g].push_back(i);
  }
  std::shared_ptr<const Scene> scene;  // the last scene loaded, kept for the next group
  std::string loaded;                  // what it was loaded as
  for (const std::string& g : order) {
    const std::vector<size_t>& points = groups[g];
    const SweepPoint& first = s.points[points.front()];
    int window = 0;
    for (size_t i : points) window = std::max(window, s.points[i].window);
    std::optional<FrameWindow> frames;
    try {
      if (!scene || loaded != first.scene) {
        status("loading " + first.scene);
        scene.reset();
        loaded.clear();
        scene = std::make_shared<const Scene>(load_scene(first.scene));
        loaded = first.scene;
      }
      status("traces of " + first.scene + " at " + first.resolution);
      WindowRequest req;
      req.first = first.frame;
      req.count = window;
      req.aniso = first.aniso;
      req.use_cache = o.use_cache;
      req.need_first_image = s.images;
      frames = load_window(scene, parse_frame_resolution(first.resolution), first.config, req);
    } catch (const Error& e) {
      for (size_t i : points) emit(failed_record(s, i, e.what(), o.command));
      continue;
    } catch (const std::bad_alloc&) {
      const std::string why = out_of_memory_message("loading " + first.scene + " at " + first.resolution);
      for (size_t i : points) emit(failed_record(s, i, why, o.command));
      continue;
    }
    status("running " + std::to_string(points.size()) + " points on " + first.scene);
    parallel_for(points.size(), o.jobs, [&](size_t k) {
      const size_t i = points[k];
      const SweepPoint& p = s.points[i];
      RunRecord r = record_of(s, i, o.command);
      const auto t0 = std::chrono::steady_clock::now();
      try {
        const SchemeResult result = run_scheme_window(p.scheme, *frames->scene, *frames->frames, p.config, p.window);
        r.status = "done";
        r.result = to_json(result);
        r.metrics = metrics_of(result);
        if (s.images && !frames->outputs.empty() && !frames->outputs.front().colour.rgba.empty())
          r.images = images_of(frames->outputs.front(), result);
      } catch (const Error& e) {
        r.status = "failed";
        r.error = e.what();
      } catch (const std::bad_alloc&) {
        r.status = "failed";
        r.error = out_of_memory_message("simulating " + p.scheme + " on " + p.scene);
      }
      r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      emit(r);
    });
  }
}

SweepPlan plan_sweep(const Sweep& s, const ResultsDb& db, bool resume, bool retry_failed) {
  SweepPlan plan;
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
  db.add_sweep(sweep_record(s, command));
  if (!plan.retried) return;
  const auto status = db.run_status();
  for (size_t i : plan.todo)
    if (status.count(s.points[i].id)) db.remove(s.points[i].id);  // a failed run, retried
}

}  // namespace oovr
