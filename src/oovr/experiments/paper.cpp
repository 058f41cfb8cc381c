#include "oovr/experiments/paper.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/parallel.h"
#include "oovr/core/text.h"
#include "oovr/core/units.h"
#include "oovr/experiments/paper_figures.h"
#include "oovr/experiments/svg_chart.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/run/frames.h"
#include "oovr/run/result_json.h"
#include "oovr/scene/load.h"
#include "oovr/timing/gpm_model.h"

namespace oovr {
namespace fs = std::filesystem;
using namespace paper;

namespace embedded {
extern const char* const paper_toml;
}

namespace {

// A setting's value in one spelling: the number in base units, shortest
// form, or the readable value.
std::string canonical_value(const Config::Entry& e) { return e.base ? format_number(*e.base) : e.value; }

// "key=value;..." of the settings of `c` that differ from `machine`, sorted.
std::string differences(const std::map<std::string, Config::Entry>& c, const std::map<std::string, Config::Entry>& machine) {
  std::string out;
  for (const auto& [key, e] : c) {
    const auto m = machine.find(key);
    const std::string v = canonical_value(e);
    if (m != machine.end() && canonical_value(m->second) == v) continue;
    out += (out.empty() ? "" : ";") + key + "=" + v;
  }
  return out;
}

std::string index_key(const std::string& scene, const std::string& resolution, const std::string& scheme,
                      const std::string& canonical) {
  return scene + "|" + resolution + "|" + scheme + "|" + canonical;
}

const std::map<std::string, Config::Entry>& machine_entries(const Config& machine) {
  check_config(machine);
  return machine.entries();
}

// A point's scene as the evaluation names it: one-pass forms under their level.
std::string base_scene(const std::string& scene) {
  const auto at = scene.find(kOnePassOption);
  if (at == std::string::npos) return scene;
  std::string s = scene.substr(0, at);
  while (!s.empty() && (s.back() == '?' || s.back() == '&')) s.pop_back();
  return s;
}

}  // namespace

const SchemeResult* PaperResults::find(const std::string& scene, const std::string& resolution, const std::string& scheme,
                                       const std::string& variant) const {
  // One-pass runs carry their texture format too (paper_figures.h).
  const std::string asked = scene.find(kOnePassOption) == std::string::npos ? variant
                            : variant.empty()                               ? kOnePassWindow
                                                                            : variant + ";" + kOnePassWindow;
  auto it = canonical.find(asked);
  if (it == canonical.end()) {
    Config c = machine;
    std::stringstream in(asked);
    std::string item;
    while (std::getline(in, item, ';'))
      if (!item.empty()) c.set(item);
    check_config(c);
    it = canonical.emplace(asked, differences(c.entries(), machine_entries(machine))).first;
  }
  const auto at = index.find(index_key(scene, resolution, scheme, it->second));
  return at == index.end() ? nullptr : &runs[at->second].result;
}

std::string paper_sweep_text() { return embedded::paper_toml; }
Sweep paper_sweep() { return parse_sweep(embedded::paper_toml, "experiments/paper.toml", ""); }

void load_evaluation(PaperOptions& o, const std::string& text, const std::string& name, const std::string& base_dir,
                     const std::string& preset, const std::vector<std::string>& settings, int frames) {
  std::map<std::string, std::string> sources;
  const std::string on_machine = sweep_on_machine(text, name, base_dir, preset, settings, frames, &sources);
  o.sweep = parse_sweep(on_machine, name, base_dir);
  o.machine = resolve_on_machine(o.sweep, sources);
  o.machine_sources = std::move(sources);
}

std::vector<MachineChange> machine_changes(const Config& machine, const std::map<std::string, std::string>& sources) {
  Config read = machine;  // every section reads it: each key's value, default and source
  check_config(read);
  std::vector<MachineChange> out;
  for (const auto& [key, e] : read.entries()) {
    if (e.source == "default" || e.value == e.fallback) continue;
    const auto it = sources.find(key);
    out.push_back({key, e.value, e.fallback, it != sources.end() ? it->second : e.source});
  }
  return out;
}

PaperResults run_paper(PaperOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  PaperResults res;
  res.machine = o.machine;
  const Sweep& s = o.sweep;
  const auto wanted = [&](const SweepPoint& p) {
    return o.only_scenes.empty() ||
           std::find(o.only_scenes.begin(), o.only_scenes.end(), base_scene(p.scene)) != o.only_scenes.end();
  };
  std::vector<std::string> names;  // the sweep's scenes, in order
  for (const auto& p : s.points)
    if (std::find(names.begin(), names.end(), base_scene(p.scene)) == names.end()) names.push_back(base_scene(p.scene));
  for (const auto& name : o.only_scenes)
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw Error("the sweep '" + s.name + "' has no scene '" + name + "' (its scenes: " + list + ")");
    }
  std::vector<size_t> which;
  for (size_t i = 0; i < s.points.size(); ++i)
    if (wanted(s.points[i])) which.push_back(i);

  // Run what the database does not hold.
  ResultsDb db(o.db);  // the one writer
  db.verify();         // whole, before its runs are kept and written up
  // Resuming after the sweep changed (another oovr's paper.toml): what the
  // sweep no longer has goes, the rest is kept; said in a note.
  const SweepPlan plan = plan_sweep(s, db, true, false, true);
  for (const auto& note : plan.notes)
    if (o.progress) o.progress(note);
  begin_sweep(s, plan, db, o.command);
  std::vector<size_t> todo;
  for (size_t i : plan.todo)
    if (wanted(s.points[i])) todo.push_back(i);
  if (o.progress && todo.size() < which.size())
    o.progress(fmt::format("{} of {} points in {} already", which.size() - todo.size(), which.size(), o.db));
  if (o.on_plan) o.on_plan(todo.size());
  SweepRunOptions ro;
  ro.jobs = o.jobs;
  ro.command = o.command;
  ro.on_status = o.progress;
  ro.on_record = o.on_record;
  run_points_into(s, todo, db, ro);
  res.ran = todo.size();

  // Read them back: the document is written from the database.
  std::map<std::string, size_t> position;
  for (size_t i : which) position[s.points[i].id] = i;
  const auto& machine = machine_entries(o.machine);
  std::map<std::string, std::string> failed;  // scene -> first error
  std::vector<std::string> done_scenes;
  std::vector<std::pair<size_t, PaperRun>> read;  // (position in the sweep, run)
  for (const RunRecord& r : db.runs()) {
    const auto p = position.find(r.id);
    if (p == position.end()) continue;
    if (r.status != "done") {
      failed.emplace(r.scene, r.error);
      continue;
    }
    SchemeResult result = scheme_result_from_stored(r.result, r.metrics);
    std::map<std::string, Config::Entry> config;
    for (const auto& [key, e] : r.config.items()) {
      Config::Entry x;
      x.value = e.at("value").get<std::string>();
      if (e.contains("base")) x.base = e.at("base").get<double>();
      config[key] = x;
    }
    const std::string canonical = differences(config, machine);
    read.push_back({p->second, {r.scene, r.resolution, r.scheme, canonical, std::move(result)}});
    RunRecord kept = r;  // for the claims (measure_claims), without what they do not read
    kept.result = nullptr;
    kept.images.clear();
    res.records.push_back(std::move(kept));
    done_scenes.push_back(r.scene);
  }
  // In the sweep file's order (the database's is its ids'), so that tables
  // and CSV files list the runs the same way whatever their ids.
  std::sort(read.begin(), read.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [at, run] : read) {
    res.index[index_key(run.scene, run.resolution, run.scheme, run.variant)] = res.runs.size();
    res.runs.push_back(std::move(run));
  }
  // The order of the sweep file; levels that ran nothing are skipped, with why.
  for (size_t i : which) {
    const std::string& scene = s.points[i].scene;
    const bool ran = std::find(done_scenes.begin(), done_scenes.end(), scene) != done_scenes.end();
    if (scene.find(kOnePassOption) != std::string::npos) {
      const std::string level = base_scene(scene);
      if (ran && std::find(res.one_pass_scenes.begin(), res.one_pass_scenes.end(), level) == res.one_pass_scenes.end())
        res.one_pass_scenes.push_back(level);
      continue;
    }
    if (ran && std::find(res.scenes.begin(), res.scenes.end(), scene) == res.scenes.end()) res.scenes.push_back(scene);
    const std::string skip = scene + ": " + (failed.count(scene) ? failed[scene] : "no run");
    if (!ran && std::find(res.skipped.begin(), res.skipped.end(), skip) == res.skipped.end()) res.skipped.push_back(skip);
  }
  if (res.scenes.empty())
    throw Error("no scene of the evaluation ran" + (res.skipped.empty() ? std::string() : " (" + res.skipped.front() + ")"));
  std::sort(res.one_pass_scenes.begin(), res.one_pass_scenes.end(), [&](const std::string& a, const std::string& b) {
    return std::find(res.scenes.begin(), res.scenes.end(), a) < std::find(res.scenes.begin(), res.scenes.end(), b);
  });

  // What the writers need to know of the runs.
  o.spec = MachineSpec::from_config(o.machine);
  o.resolutions.clear();
  o.sweep_resolution.clear();
  for (size_t i : which) {
    const SweepPoint& p = s.points[i];
    if (p.settings.empty() && std::find(o.resolutions.begin(), o.resolutions.end(), p.resolution) == o.resolutions.end())
      o.resolutions.push_back(p.resolution);
    if (o.sweep_resolution.empty() && p.swept.count("link.bandwidth")) o.sweep_resolution = p.resolution;
  }
  if (o.sweep_resolution.empty())
    o.sweep_resolution = o.resolutions.empty() ? s.points[which.front()].resolution : o.resolutions.back();
  const SweepPoint& first = s.points[which.front()];
  o.first_frame = first.frame;
  o.frames = first.window;
  o.aniso = first.aniso;
  o.steps = res.find(res.scenes.front(), o.sweep_resolution, kSteps.front().baseline, kSteps.front().settings) != nullptr;
  o.copies = res.find(res.scenes.front(), o.sweep_resolution, "oo-vr", copy_variant(kCopyCapacities.front().first)) != nullptr;
  o.workloads = !res.one_pass_scenes.empty();

  // Each scene's statistics at the sweep resolution, from its first frame
  // (the trace cache has it): scenes loaded at once, on the sweep's workers,
  // since loading a game level is most of it.
  std::vector<PaperSceneStats> stats(res.scenes.size());
  parallel_for(res.scenes.size(), o.jobs, [&](size_t k) {
    const auto loaded = std::make_shared<const Scene>(load_scene(res.scenes[k]));
    const Scene& scene = *loaded;
    WindowRequest w;
    w.first = o.first_frame;
    w.count = 1;
    w.aniso = o.aniso;
    const FrameWindow window = load_window(loaded, parse_frame_resolution(o.sweep_resolution), o.spec, w);
    PaperSceneStats& st = stats[k];
    st.draws = scene.draws(o.first_frame).size();
    st.triangles = scene.triangle_count(o.first_frame);
    for (const auto& t : scene.textures) st.texture_bytes += t.bytes();
    const TimingSpec& timing = o.spec.timing;
    double vi = 0, fi = 0;
    const std::shared_ptr<const FrameTrace> trace = window.frames->at(0);
    for (const auto& ow : trace->objects) vi += double(ow.vertices) * timing.vertex_instructions;
    for (const auto& tw : trace->tiles)
      fi += timing.fragment_work(tw.quads, uint64_t(tw.quads) * 4 * trace->objects[tw.object].fragment_instructions);
    st.vertex_share = vi + fi > 0 ? vi / (vi + fi) : 0;
  });
  for (size_t k = 0; k < res.scenes.size(); ++k) res.stats[res.scenes[k]] = stats[k];
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

namespace {

void write_file(const fs::path& path, const std::string& text) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  write_output_file(path.string(), text, "output");
}

}  // namespace

void write_paper_outputs(const PaperResults& r, const PaperOptions& o, const std::string& dir) {
  const fs::path d(dir);
  Figures F{r, o};
  nlohmann::ordered_json j = results_header(o.command);
  j["config"] = to_json(o.spec.entries);  // every key, described
  j["scenes"] = r.scenes;
  j["skipped"] = r.skipped;
  j["frames"] = o.frames;
  j["first_frame"] = o.first_frame;
  j["seconds"] = r.seconds;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const auto& x : r.runs) {
    nlohmann::ordered_json e;
    e["scene"] = x.scene;
    e["resolution"] = x.resolution;
    e["variant"] = x.variant;
    e["result"] = to_json(x.result);
    runs.push_back(e);
  }
  j["runs"] = runs;
  write_file(d / "results.json", j.dump(1) + "\n");

  std::string fig15 = "scene,resolution,scheme,latency_ms,throughput_fps,speedup_vs_baseline,throughput_vs_baseline\n";
  std::string fig16 = "scene,resolution,scheme,inter_gpm_bytes,traffic_vs_baseline";
  for (int c = 0; c < kCategories; ++c) fig16 += std::string(",") + category_name(Category(c));
  fig16 += "\n";
  for (const auto& x : r.runs) {
    if (!x.variant.empty()) continue;
    const SchemeResult* base = r.find(x.scene, x.resolution, "baseline");
    fig15 += fmt::format("{},{},{},{:.6f},{:.2f},{:.4f},{:.4f}\n", csv_field(x.scene), x.resolution, x.scheme,
                         x.result.frame_latency_s * 1e3, x.result.throughput_fps,
                         base->frame_latency_s / x.result.frame_latency_s, x.result.throughput_fps / base->throughput_fps);
    fig16 += fmt::format("{},{},{},{},{:.4f}", csv_field(x.scene), x.resolution, x.scheme, x.result.total_inter_gpm_bytes(),
                         F.traffic(x.scene, x.resolution, x.scheme));
    for (int c = 0; c < kCategories; ++c) fig16 += fmt::format(",{}", x.result.inter_gpm_bytes[size_t(c)]);
    fig16 += "\n";
  }
  write_file(d / "fig15-speedup.csv", fig15);
  write_file(d / "fig16-traffic.csv", fig16);
  std::string fig17 = "scene,scheme,link_GBps,speedup_vs_baseline_64GBps\n", fig18 = "scene,scheme,gpms,speedup_vs_1_gpm\n";
  for (const auto& s : r.scenes)
    for (const auto& sc : kSweepSchemes) {
      for (const auto& [bw, gbps] : kLinks) fig17 += fmt::format("{},{},{},{:.4f}\n", csv_field(s), sc, gbps, F.link(s, sc, bw));
      for (int n : kGpms) fig18 += fmt::format("{},{},{},{:.4f}\n", csv_field(s), sc, n, F.gpms(s, sc, n));
    }
  write_file(d / "fig17-links.csv", fig17);
  write_file(d / "fig18-gpms.csv", fig18);
  std::string abl = "scene,scheme,variant,speedup_vs_baseline\n";
  for (const auto& s : r.scenes)
    for (const auto& [label, key] : kMechanisms) {
      abl += fmt::format("{},oo-vr,{}={},{:.4f}\n", csv_field(s), key, off_value(key),
                         F.speedup(s, o.sweep_resolution, "oo-vr", key + "=" + off_value(key)));
      abl += fmt::format("{},oo-app,{}={},{:.4f}\n", csv_field(s), key, on_value(key),
                         F.speedup(s, o.sweep_resolution, "oo-app", key + "=" + on_value(key)));
    }
  write_file(d / "ablations.csv", abl);
  if (o.copies) {
    std::string cp = "scene,copy_capacity_bytes,speedup_vs_baseline,traffic_vs_baseline,copies_peak_bytes\n";
    for (const auto& s : r.scenes)
      for (const auto& [cap, bytes] : copy_points(F.dram_bytes())) {
        const SchemeResult* x = r.find(s, o.sweep_resolution, "oo-vr", copy_variant(cap));
        cp += fmt::format("{},{:.0f},{:.4f},{:.4f},{:.0f}\n", csv_field(s), bytes, F.copies_speedup(s, cap),
                          F.copies_traffic(s, cap), x ? scheme_metric(*x, "copies.peak_bytes") : std::nan(""));
      }
    write_file(d / "copies.csv", cp);
  }

  write_paper_plots(r, o, dir);
}

void write_paper_plots(const PaperResults& r, const PaperOptions& o, const std::string& dir) {
  const fs::path d(dir);
  Figures F{r, o};
  // Plots at the sweep resolution.
  const std::vector<std::string> shown = {"baseline-1tb", "afr", "sfr-v", "sfr-h", "object", "oo-app", "oo-vr"};
  std::vector<std::vector<double>> sp, tr;
  std::vector<std::string> groups = r.scenes;
  groups.push_back("geomean");
  for (const auto& s : r.scenes) {
    sp.emplace_back();
    tr.emplace_back();
    for (const auto& sc : shown) {
      sp.back().push_back(F.speedup(s, o.sweep_resolution, sc));
      tr.back().push_back(F.traffic(s, o.sweep_resolution, sc));
    }
  }
  sp.emplace_back();
  tr.emplace_back();
  for (const auto& sc : shown) {
    sp.back().push_back(F.mean([&](const std::string& s) { return F.speedup(s, o.sweep_resolution, sc); }));
    tr.back().push_back(F.mean([&](const std::string& s) { return F.traffic(s, o.sweep_resolution, sc); }));
  }
  // Whiskers: the frame-by-frame speed-ups' range on each scene (none on
  // the geomean, a mean over scenes).
  std::vector<std::vector<std::pair<double, double>>> spread;
  for (const auto& s : r.scenes) {
    spread.emplace_back();
    for (const auto& sc : shown) spread.back().push_back(F.speedup_range(s, o.sweep_resolution, sc));
  }
  write_file(d / "fig15-speedup.svg",
             bar_chart("Single-frame speed-up over the baseline (" + o.sweep_resolution + ")", "speed-up (baseline = 1)", groups,
                       shown, sp, 1.0, spread, "whiskers: frames' range"));
  write_file(d / "fig16-traffic.svg", bar_chart("Inter-GPM traffic against the baseline (" + o.sweep_resolution + ")",
                                                "traffic (baseline = 1)", groups, shown, tr, 1.0));
  std::vector<double> xs;
  std::vector<std::string> xn;
  for (const auto& [bw, gbps] : kLinks) {
    xs.push_back(gbps);
    xn.push_back(gbps >= 1000 ? "1 TB/s" : fmt::format("{:.0f}", gbps));
  }
  std::vector<std::vector<double>> lv, gv;
  for (const auto& sc : kSweepSchemes) {
    lv.emplace_back();
    for (const auto& link : kLinks) {
      const std::string& bw = link.first;  // (Clang 14 cannot capture structured bindings.)
      lv.back().push_back(F.mean([&](const std::string& s) { return F.link(s, sc, bw); }));
    }
    gv.emplace_back();
    for (int n : kGpms) gv.back().push_back(F.mean([&](const std::string& s) { return F.gpms(s, sc, n); }));
  }
  write_file(d / "fig17-links.svg",
             line_chart("Speed-up over the baseline at " + machine_value(o, "link.bandwidth") + " (geomean of scenes)",
                        "link bandwidth (GB/s)", "speed-up", xs, xn, kSweepSchemes, lv, true));
  std::vector<double> gx;
  std::vector<std::string> gn;
  for (int n : kGpms) {
    gx.push_back(n);
    gn.push_back(std::to_string(n));
  }
  write_file(d / "fig18-gpms.svg",
             line_chart("Speed-up over one GPM (geomean of scenes)", "GPMs", "speed-up", gx, gn, kSweepSchemes, gv, true));
  if (o.copies) {
    std::vector<double> cx;
    std::vector<std::string> cn;
    const auto points = copy_points(F.dram_bytes());
    for (const auto& [cap, bytes] : points) {
      cx.push_back(bytes);
      cn.push_back(format_bytes(Bytes{uint64_t(bytes)}));
    }
    std::vector<std::vector<double>> cv;
    for (const auto& s : r.scenes) {
      cv.emplace_back();
      for (const auto& point : points) cv.back().push_back(F.copies_speedup(s, point.first));
    }
    write_file(d / "copies.svg",
               line_chart("OO-VR's speed-up over the baseline against copy capacity per GPM (" + o.sweep_resolution + ")",
                          "copy capacity per GPM", "speed-up", cx, cn, r.scenes, cv, true));
  }
}

}  // namespace oovr
