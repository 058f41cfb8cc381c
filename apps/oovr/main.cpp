// oovr: the command-line tool (DESIGN.md, "Commands").
#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <new>
#include <nlohmann/json.hpp>
#include <system_error>

#include "commands.h"
#include "oovr/core/config.h"
#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/core/text.h"
#include "oovr/core/version.h"
#include "oovr/experiments/capture_check.h"
#include "oovr/experiments/report.h"
#include "oovr/pipeline/frame_summary.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/run/simulation.h"
#include "oovr/scene/formats/apitrace.h"
#include "oovr/scene/load.h"
#include "oovr/scene/scene_info.h"
#include "oovr/schemes/i_scheme.h"

namespace {

using namespace oovr;

std::string human_bytes(uint64_t b) {
  if (b >= (1ull << 30)) return fmt::format("{:.2f} GiB", double(b) / double(1ull << 30));
  if (b >= (1ull << 20)) return fmt::format("{:.2f} MiB", double(b) / double(1ull << 20));
  if (b >= (1ull << 10)) return fmt::format("{:.1f} KiB", double(b) / double(1ull << 10));
  return fmt::format("{} B", b);
}

int cmd_scenes() {
  const auto scenes = list_scenes();
  size_t w = 4;
  for (const auto& s : scenes) w = std::max(w, s.name.size());
  fmt::print("{:<{}}  {:<9}  {}\n", "name", w, "kind", "description");
  for (const auto& s : scenes) fmt::print("{:<{}}  {:<9}  {}\n", s.name, w, s.kind, s.description);
  fmt::print("\nAny OBJ, glTF (.gltf/.glb), PLY or AC3D (.ac) file path is also a scene.\n");
  fmt::print("OpenArena maps take options: oa:MAP?group=shader-lightmap|face&tess=1..16\n");
  return 0;
}

// Every registered scheme (one file each in src/oovr/schemes/impl/), with
// what it models.
int cmd_schemes() {
  const auto names = Schemes::names();
  size_t w = 4;
  for (const auto& n : names) w = std::max(w, n.size());
  fmt::print("{:<{}}  {}\n", "name", w, "description");
  for (const auto& n : names) fmt::print("{:<{}}  {}\n", n, w, Schemes::find(n)->description);
  return 0;
}

struct SceneInfoArgs {
  std::string scene;
  bool json = false;
};

int cmd_scene_info(const SceneInfoArgs& a) {
  const Scene scene = load_scene(a.scene);
  const SceneInfo i = scene_info(scene);
  if (a.json) {
    fmt::print("{}\n", scene_info_json(i, scene.notes).dump(2));
    return 0;
  }
  fmt::print("scene          {}\n", i.name);
  fmt::print("draws          {}{}\n", i.draws,
             i.draws_max ? fmt::format(" in the first frame; per frame median {}, from {} to {}", i.draws_median, i.draws_min,
                                       i.draws_max)
                         : "");
  fmt::print("triangles      {}\n", i.triangles);
  fmt::print("vertices       {}\n", i.vertices);
  fmt::print("textures       {} ({} with mip chains)\n", i.textures, human_bytes(i.texture_bytes));
  fmt::print("layers         {} sampled over the draws ({:.2f} per draw); {} draws lit per pixel\n", i.texture_layers,
             i.draws ? double(i.texture_layers) / double(i.draws) : 0.0, i.lit_draws);
  fmt::print("camera frames  {}\n", i.camera_frames);
  fmt::print("\nobjects sharing each texture:\n");
  fmt::print("  {:<28} {:>11} {:>10} {:>8}\n", "texture", "size", "bytes", "objects");
  for (const auto& t : i.texture_use) {
    // Long names (archive paths) keep their end, where the file name is.
    const std::string name = t.name.size() > 28 ? "..." + t.name.substr(t.name.size() - 25) : t.name;
    fmt::print("  {:<28} {:>11} {:>10} {:>8}\n", name, fmt::format("{}x{}", t.width, t.height), human_bytes(t.bytes), t.objects);
  }
  fmt::print("\nsharing histogram (objects per texture: textures):");
  for (const auto& [objects, textures] : i.sharing_histogram) fmt::print(" {}:{}", objects, textures);
  fmt::print("\n");
  if (!scene.notes.empty()) {
    fmt::print("\nloader notes:\n");
    for (const auto& n : scene.notes) fmt::print("  {}\n", n);
  }
  return 0;
}

struct ConfigArgs {
  std::string file;
  std::vector<std::string> settings;
  bool all = false;
};

int cmd_config(const ConfigArgs& a) {
  const Config c = cli::machine_config(a.file, a.settings);
  check_config(c);
  if (a.all) {
    // Every key a component declares, with its value, default, where the
    // value came from, what it takes and what it means. A key whose default
    // is the scheme's (OO-VR's switches) is listed even when not given.
    struct Row {
      std::string key, value, fallback, source, takes, meaning;
    };
    std::vector<Row> rows;
    for (const auto& section : ConfigSections::names())
      for (const ConfigKey& k : ConfigSections::find(section)->keys) {
        const auto it = c.entries().find(k.key);
        if (it != c.entries().end())
          rows.push_back({k.key, it->second.value, it->second.fallback, it->second.source, it->second.kind, k.meaning});
        else rows.push_back({k.key, "-", k.user_default, "the scheme's", k.takes, k.meaning});
      }
    std::sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) { return x.key < y.key; });
    size_t w[5] = {3, 5, 7, 6, 5};
    for (const Row& r : rows) {
      w[0] = std::max(w[0], r.key.size());
      w[1] = std::max(w[1], r.value.size());
      w[2] = std::max(w[2], r.fallback.size());
      w[3] = std::max(w[3], r.source.size());
      w[4] = std::max(w[4], r.takes.size());
    }
    const auto line = [&](const Row& r) {
      fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", r.key, w[0], r.value, w[1], r.fallback, w[2], r.source, w[3],
                 r.takes, w[4], r.meaning);
    };
    line({"key", "value", "default", "source", "takes", "meaning"});
    for (const Row& r : rows) line(r);
    return 0;
  }
  // Printed as TOML (dotted keys), so that the output is itself a preset.
  fmt::print("# {}\n{}", a.file.empty() ? "built-in defaults (the paper's Table 1, as configs/paper-table1.toml)" : a.file,
             resolved_toml(c));
  return 0;
}

struct RenderArgs {
  std::string scene;
  int frame = 0;
  std::string resolution = "1280x1024";
  std::string eye_resolution;
  std::string out;
  int aniso = 16;
  float ipd_mm = 64.0f;
  unsigned threads = 0;
};

int cmd_render(const RenderArgs& a) {
  check_output_path(a.out, "image");
  PipelineSettings settings;
  settings.max_anisotropy = a.aniso;
  settings.threads = a.threads;
  settings.validate();
  check_image_path(a.out);
  StereoRig rig = a.eye_resolution.empty() ? parse_frame_resolution(a.resolution) : parse_eye_resolution(a.eye_resolution);
  rig.ipd_m = a.ipd_mm / 1000.0f;
  const auto t0 = std::chrono::steady_clock::now();
  const Scene scene = load_scene(a.scene);
  const StereoView view = make_stereo_view(scene.camera, a.frame, rig);
  const auto t1 = std::chrono::steady_clock::now();
  const FrameOutput out = render_frame(scene, view, settings, a.frame);
  const auto t2 = std::chrono::steady_clock::now();
  write_image(out.colour, a.out);

  const FrameSummary sum = summarise(out);
  const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
  fmt::print("{}: frame {} of {}, {}x{} stereo ({}x{} per eye) -> {}\n", scene.name, a.frame, scene.camera.frames.size(),
             view.frame_width, view.frame_height, rig.eye_width, rig.eye_height, a.out);
  fmt::print("  draws {}, triangles {}, set up left {} right {}, culled (back-facing or outside the view) {}\n",
             scene.draws(a.frame).size(), scene.triangle_count(a.frame), sum.setup[0], sum.setup[1], sum.culled);
  fmt::print("  fragments covered {}, shaded {}, passed {}; quads {}\n", sum.covered, sum.shaded, sum.passed, sum.quads);
  fmt::print("  trace: {} (object, eye, tile) records, {} texture line reads ({}-byte lines)\n", sum.records,
             sum.texture_line_reads, sum.line_bytes);
  // Texture work: layers sampled per shaded fragment and per pixel drawn
  // (the frame's pixels some draw wrote), and the texture bytes touched.
  fmt::print("  texture: {:.2f} layers per shaded fragment, {:.2f} per pixel drawn; {} of texture lines touched\n",
             sum.layers_per_shaded(), sum.layers_per_pixel(), human_bytes(sum.texture_bytes_touched));
  fmt::print("  time: scene {:.0f} ms, render {:.0f} ms\n", ms(t1 - t0), ms(t2 - t1));
  return 0;
}

// CLI11's Range lets NaN through (every comparison with it is false).
const CLI::Validator kFinite(
    [](std::string& text) {
      double v = 0;
      const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
      if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v))
        return std::string("'" + text + "' is not a finite number");
      return std::string();
    },
    "FINITE");

// A whole number from 0 (CLI11's NonNegativeNumber names its bound as a
// 309-digit double).
const CLI::Validator kWhole(
    [](std::string& text) {
      long long v = 0;
      const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
      if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < 0)
        return std::string("'" + text + "' is not a whole number from 0");
      return std::string();
    },
    "WHOLE >= 0");

// An option given with an empty value ("--config ''") is an error, never
// the default.
void check_no_empty_values(const CLI::App& cmd) {
  for (const CLI::Option* o : cmd.get_options()) {
    if (!o->count() || o->get_expected_min() == 0) continue;
    const std::string& name = o->get_name();
    for (const auto& r : o->results())
      if (r.find_first_not_of(" \t") == std::string::npos) throw Error(name + " is empty: give a value, or leave the option out");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"oovr: stereo VR rendering on NUMA multi-GPU systems (OO-VR, ISCA 2019)"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every command");

  app.set_version_flag("--version", fmt::format("oovr {} (commit {})", version(), git_commit()));

  app.add_subcommand("scenes", "List built-in and installed scenes");
  app.add_subcommand("schemes", "List the registered schemes with what each models");

  SceneInfoArgs info;
  auto* info_cmd = app.add_subcommand("scene-info", "Draws, triangles, textures and texture sharing of a scene");
  info_cmd->add_option("--scene", info.scene, "Scene name or model file")->required();
  info_cmd->add_flag("--json", info.json, "Print JSON instead of text");

  ConfigArgs config;
  auto* config_cmd = app.add_subcommand("config", "Print the machine configuration in force (preset + overrides)");
  config_cmd->add_option("--config", config.file, "TOML preset (default: the paper's Table 1)");
  config_cmd->add_option("--set", config.settings, "Override a key, e.g. --set link.bandwidth=128GBps (repeatable)");
  config_cmd->add_flag("--all", config.all, "List every key with its value, default, source and what it takes");

  cli::SimulateArgs sim;
  auto add_machine_options = [](CLI::App* cmd, cli::SimulateArgs& a) {
    cmd->add_option("--scene", a.scene, "Scene name or model file")->required();
    cmd->add_option("--frame", a.frame, "First frame of the camera path")->check(kWhole);
    cmd->add_option("--resolution", a.resolution, "Whole stereo frame WxH")->capture_default_str();
    cmd->add_option("--eye-resolution", a.eye_resolution, "Resolution of one eye WxH (instead of --resolution)");
    cmd->add_option("--aniso", a.aniso, "Maximum anisotropic filtering taps")->capture_default_str()->check(CLI::Range(1, 16));
    cmd->add_option("--config", a.config, "TOML machine preset (default: the paper's Table 1)");
    cmd->add_option("--set", a.settings, "Override a configuration key, e.g. --set link.bandwidth=128GBps (repeatable)");
    cmd->add_option("--json", a.json, "Write the results as JSON");
    cmd->add_flag("--no-cache", a.no_cache, "Render every frame even when its trace is cached ($OOVR_CACHE_DIR)");
  };
  auto* sim_cmd = app.add_subcommand("simulate", "Replay a scene's frame through one scheme");
  add_machine_options(sim_cmd, sim);
  sim_cmd->add_option("--scheme", sim.scheme, "Scheme (oovr compare --help lists them)")->required();
  sim_cmd->add_option("--frames", sim.frames, "Frames to measure, from --frame on (default: one per GPM)")
      ->check(CLI::Range(1, 1000));
  sim_cmd->add_option("--gpm-image", sim.gpm_image, "Write the frame coloured by the GPM that shaded each pixel");
  sim_cmd->add_option("--traffic-image", sim.traffic_image, "Write inter-GPM bytes per screen tile as a heat map");
  sim_cmd->add_option("--timeline", sim.timeline,
                      "Write every unit of work as Trace Event Format JSON (Perfetto, chrome://tracing)");
  sim_cmd->add_option("--timeline-events", sim.timeline_events, "At most this many units in the timeline, the earliest")
      ->capture_default_str()
      ->check(CLI::Range(size_t(1), size_t(100'000'000)));

  cli::SimulateArgs cmp;
  std::string scheme_list;
  const std::vector<std::string> ordered = default_compare_schemes();
  std::string all_schemes;
  for (const auto& n : ordered) all_schemes += (all_schemes.empty() ? "" : ",") + n;
  auto* cmp_cmd = app.add_subcommand("compare", "Run several schemes on the same frame, normalised to baseline");
  add_machine_options(cmp_cmd, cmp);
  cmp_cmd->add_option("--frames", cmp.frames, "Frames to measure every scheme on, from --frame on (default: one per GPM)")
      ->check(CLI::Range(1, 1000));
  cmp_cmd->add_option("--schemes", scheme_list, "Comma-separated schemes (default: all: " + all_schemes + ")");

  cli::SweepArgs sweep;
  auto* sweep_cmd = app.add_subcommand("sweep", "Run a sweep file's points into a results database (here or on SLURM)");
  sweep_cmd->add_option("file", sweep.file, "Sweep definition (TOML; docs/sweeps.md)");
  sweep_cmd->add_option("--db", sweep.db, "Results database (default: the sweep file's name with .db, here)");
  sweep_cmd->add_flag("--resume", sweep.resume, "Run only the points the database does not hold yet");
  sweep_cmd->add_flag("--retry-failed", sweep.retry_failed, "Run again the points that failed (and those missing)");
  sweep_cmd->add_option("--set", sweep.settings,
                        "Override a key of the file's [set] for every point (repeatable; not a key it sweeps)");
  sweep_cmd->add_flag("--reconcile", sweep.reconcile,
                      "The database holds this sweep from an edited file: keep the runs the file still has, delete the others");
  sweep_cmd->add_option("--jobs", sweep.jobs, "Points run at once (0 = every core)")->capture_default_str();
  sweep_cmd->add_option("--backend", sweep.backend, "Where the points run")
      ->capture_default_str()
      ->check(CLI::IsMember({"local", "slurm"}));
  sweep_cmd->add_flag("--no-cache", sweep.no_cache, "Render every frame even when its trace is cached ($OOVR_CACHE_DIR)");
  sweep_cmd->add_flag("--collect", sweep.collect, "Merge the SLURM tasks' result files into the database");
  sweep_cmd->add_flag("--list", sweep.list, "Print the points with their ids and settings; run nothing");
  const char* slurm_group = "SLURM (--backend slurm, --collect)";
  sweep_cmd->add_option("--slurm-dir", sweep.slurm_dir, "Job folder: script, manifest, task logs and results (default: DB.slurm)")
      ->group(slurm_group);
  sweep_cmd->add_option("--partition", sweep.partition, "Partition to submit to (default: the cluster's)")->group(slurm_group);
  sweep_cmd->add_option("--time-limit", sweep.time_limit, "Time limit per task, as sbatch --time takes it")->group(slurm_group);
  sweep_cmd->add_option("--array-limit", sweep.array_limit, "Tasks running at once (0 = no limit)")
      ->check(CLI::Range(0, 1000000))
      ->group(slurm_group);
  sweep_cmd->add_option("--chunk", sweep.chunk, "Points per task (0 = a task per trace group, at most 1000 tasks)")
      ->check(CLI::Range(0, 1000000))
      ->group(slurm_group);
  sweep_cmd->add_option("--cpus-per-task", sweep.cpus_per_task, "CPUs per task; a task runs that many points at once")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024))
      ->group(slurm_group);
  sweep_cmd->add_flag("--wait", sweep.wait, "Wait for the job to end, then collect")->group(slurm_group);
  sweep_cmd->add_option("--sbatch-arg", sweep.sbatch_args, "Pass an argument to sbatch (repeatable)")->group(slurm_group);
  sweep_cmd->add_option("--task", sweep.task, "Run one task of --slurm-dir (what the job script runs)")
      ->check(CLI::Range(0, 100000000))
      ->group(slurm_group);

  ReportOptions report;
  auto* report_cmd = app.add_subcommand("report", "Plots and an HTML page from a results database");
  report_cmd->add_option("db", report.db, "Results database (oovr sweep)")->required();
  report_cmd->add_option("--out", report.out, "Folder for index.html and the plots")->required();
  report_cmd
      ->add_option("--plots", report.plots,
                   "Comma-separated rows of each study figure: latency, speedup, throughput, traffic, energy "
                   "(default: latency,speedup,traffic,energy, those the database can fill)")
      ->delimiter(',');
  report_cmd->add_option("--x", report.x, "Comma-separated: plot against only these swept keys (default: every swept key)")
      ->delimiter(',');
  report_cmd->add_option("--group", report.group, "Panels per scene (a line per scheme) or per scheme (a line per scene)")
      ->check(CLI::IsMember({"scene", "scheme"}))
      ->capture_default_str();
  report_cmd->add_option("--normalise", report.normalise, "The scheme speed-ups are over (its run of the same setup)")
      ->capture_default_str();
  report_cmd->add_flag("--own-y", report.own_y, "Each panel of an absolute row (latency, traffic, energy) its own y axis");

  RenderArgs render;
  // What oovr paper and oovr beyond both take: the scenes, the machine and
  // the frames every point runs on, and how the work is run.
  const auto evaluation_options = [](CLI::App* cmd, cli::PaperArgs& a) {
    cmd->add_option("--scenes", a.scenes, "Comma-separated: only these scenes of the sweep (default: all)");
    cmd->add_flag("--resume", a.resume, "Keep the database in --out and run only the points it lacks");
    cmd->add_option("--jobs", a.jobs, "Points run at once (0 = every core)")->capture_default_str();
    cmd->add_option("--config", a.config, "TOML machine preset every point runs on (default: the paper's Table 1)");
    cmd->add_option("--set", a.settings,
                    "A key of the machine every point runs on, e.g. --set memory.copies.capacity=4GB (repeatable; points "
                    "that set the key keep their own value)");
    cmd->add_option("--frames", a.frames,
                    "Frames every point measures (default: the sweep file's; AFR needs a multiple of the GPMs)")
        ->check(CLI::Range(1, 1000));
  };
  cli::PaperArgs paper;
  auto* paper_cmd = app.add_subcommand(
      "paper", "Run the paper's evaluation (a sweep) and write the comparison with the paper from its database");
  paper_cmd->add_option("--sweep", paper.sweep, "The evaluation's sweep file (default: experiments/paper.toml, carried by oovr)");
  paper_cmd->add_option("--out", paper.out, "Folder for the database, results.json, CSV, plots and paper-comparison.md")
      ->capture_default_str();
  paper_cmd->add_option("--doc", paper.doc, "Also write the comparison here, plots beside it (e.g. docs/paper-comparison.md)");
  evaluation_options(paper_cmd, paper);
  paper_cmd->add_option("--against", paper.against,
                        "Another `oovr paper` database (another machine): also write its claims beside these, "
                        "paper-against.md and claims-against.csv in --out");

  cli::PaperArgs beyond;
  beyond.out = "out/beyond";
  auto* beyond_cmd = app.add_subcommand(
      "beyond",
      "Run the study beyond the paper (per-eye, sfr-lb, GPUpd, CHOPIN, OO-VR with screen affinity; a sweep) and write its "
      "document from its database");
  beyond_cmd->add_option("--sweep", beyond.sweep, "The study's sweep file (default: experiments/beyond.toml, carried by oovr)");
  beyond_cmd->add_option("--out", beyond.out, "Folder for the database, CSV, plots and beyond-paper.md")->capture_default_str();
  beyond_cmd->add_option("--doc", beyond.doc, "Also write the document here, plots beside it (e.g. docs/beyond-paper.md)");
  evaluation_options(beyond_cmd, beyond);

  cli::CorrelateArgs corr;
  auto* corr_cmd = app.add_subcommand("correlate", "Set oovr's frame times beside those measured on a real GPU");
  corr_cmd->add_option("--hardware", corr.hardware, "CSV of measured frames (oovr-reference --time; docs/data/hardware/)")
      ->required();
  corr_cmd->add_option("--scheme", corr.scheme, "Scheme simulating the GPU")->capture_default_str();
  corr_cmd->add_option("--config", corr.config, "TOML machine preset (default: the paper's Table 1)");
  corr_cmd->add_option("--set", corr.settings, "Override a configuration key (repeatable)");
  corr_cmd->add_option("--json", corr.json, "Write the points and statistics as JSON");
  corr_cmd->add_flag("--per-frame", corr.per_frame, "Print every frame, not only the medians");
  corr_cmd->add_flag("--no-cache", corr.no_cache, "Render every frame even when its trace is cached");
  corr_cmd->add_option("--sweep", corr.sweep,
                       "key=v1,v2,...: correlate at each value of a key and name the one that makes oovr most proportional to "
                       "the GPU (calibration)");
  corr_cmd->add_option("--min-r", corr.min_r, "Fail when Pearson r of the medians is below this")
      ->check(kFinite & CLI::Range(-1.0, 1.0));
  corr_cmd->add_option("--max-spread", corr.max_spread, "Fail when the largest ratio oovr/GPU over the smallest exceeds this")
      ->check(kFinite & CLI::Range(1.0, 1e9));

  std::string cut_in, cut_out;
  int cut_last = 0;
  auto* cut_cmd = app.add_subcommand("trace-cut", "Keep an apitrace capture's frames up to one (scripts/capture-frames.sh)");
  cut_cmd->add_option("--in", cut_in, "The capture (an apitrace file)")->required();
  cut_cmd->add_option("--out", cut_out, "The file to write")->required();
  cut_cmd->add_option("--last-frame", cut_last, "The last frame kept (from 0)")->required()->check(kWhole);

  cli::CheckCaptureArgs check;
  auto* check_cmd = app.add_subcommand("check-capture",
                                       "Compare a captured game's frames, drawn by oovr, with glretrace's snapshots of them, "
                                       "or a capture of a built-in scene with the scene (the round trip)");
  check_cmd->add_option("--scene", check.scene, "A captured game (oa-demo:NAME, trace:PATH)")->required();
  auto* snapshots_opt =
      check_cmd->add_option("--snapshots", check.snapshots, "glretrace's snapshots (glretrace -s DIR/ --call-nos=false)");
  auto* against_opt = check_cmd->add_option(
      "--against", check.against, "The scene that was captured (oovr-reference --fixed-function): compare with it instead");
  snapshots_opt->excludes(against_opt);
  check_cmd->add_option("--min-psnr", check.min_psnr, "PSNR (dB) a frame must reach")->capture_default_str()->check(kFinite);
  check_cmd->add_option("--min-frames", check.min_frames, "With --snapshots: frames that must reach it")
      ->capture_default_str()
      ->check(kWhole);
  check_cmd
      ->add_option("--max-fragment-diff", check.max_fragment_diff,
                   "With --against: most a frame's covered or passed fragments may differ (%)")
      ->capture_default_str()
      ->check(kFinite & CLI::Range(0.0, 100.0));
  check_cmd->add_option("--images", check.images, "With --snapshots: write oovr's image of each frame into this folder");

  auto* render_cmd = app.add_subcommand("render", "Render one stereo frame to an image");
  render_cmd->add_option("--scene", render.scene, "Scene name or model file")->required();
  render_cmd->add_option("--frame", render.frame, "Frame of the camera path")->check(kWhole);
  render_cmd->add_option("--resolution", render.resolution, "Whole stereo frame WxH (both eyes side by side)")
      ->capture_default_str();
  render_cmd->add_option("--eye-resolution", render.eye_resolution, "Resolution of one eye WxH (instead of --resolution)");
  render_cmd->add_option("--out", render.out, "Output image (.png or .jpg)")->required();
  render_cmd->add_option("--aniso", render.aniso, "Maximum anisotropic filtering taps (1 = off)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  render_cmd->add_option("--ipd", render.ipd_mm, "Interpupillary distance in millimetres")
      ->capture_default_str()
      ->check(kFinite & CLI::Range(0.0f, 1000.0f));
  render_cmd->add_option("--threads", render.threads, "Worker threads (0 = all cores)")->capture_default_str();

  try {
    // CLI11 would report an unknown command as a missing one; name it.
    if (argc > 1 && argv[1][0] != '-') {
      bool known = false;
      for (const auto* sub : app.get_subcommands({})) known = known || sub->get_name() == argv[1];
      if (!known) {
        std::string commands;
        for (const auto* sub : app.get_subcommands({})) commands += (commands.empty() ? "" : ", ") + sub->get_name();
        throw Error(std::string("unknown command '") + argv[1] + "' (commands: " + commands + "; see --help)");
      }
    }
    app.parse(argc, argv);
    for (const CLI::App* cmd : app.get_subcommands()) {
      check_no_empty_values(*cmd);
      // Contradictory options are refused, not resolved by a silent rule.
      if (cmd->get_option_no_throw("--eye-resolution") && cmd->count("--resolution") && cmd->count("--eye-resolution"))
        throw Error("give --resolution or --eye-resolution, not both");
    }
    // The command line results record, with the program as "oovr".
    std::vector<const char*> words(argv, argv + argc);
    words[0] = "oovr";
    sim.command = cmp.command = paper.command = beyond.command = corr.command = sweep.command =
        shell_command_line(argc, words.data());
    const auto run = [&]() -> int {
      if (app.got_subcommand("scenes")) return cmd_scenes();
      if (app.got_subcommand("schemes")) return cmd_schemes();
      if (app.got_subcommand(info_cmd)) return cmd_scene_info(info);
      if (app.got_subcommand(config_cmd)) return cmd_config(config);
      if (app.got_subcommand(sim_cmd)) return cli::simulate(sim);
      if (app.got_subcommand(cmp_cmd)) {
        const std::vector<std::string> list = split_list(cmp_cmd->count("--schemes") ? scheme_list : all_schemes);
        if (list.empty()) throw Error("--schemes names no scheme");
        return cli::compare(cmp, list);
      }
      if (app.got_subcommand(render_cmd)) return cmd_render(render);
      if (app.got_subcommand(check_cmd)) return cli::check_capture(check);
      if (app.got_subcommand(cut_cmd)) {
        const uint64_t kept = apitrace::cut_trace(cut_in, cut_out, cut_last);
        fmt::print("trace-cut: frames 0 to {} of {} kept in {} ({} bytes)\n", cut_last, printable(cut_in), printable(cut_out),
                   kept);
        return 0;
      }
      if (app.got_subcommand(corr_cmd)) return cli::correlate(corr);
      if (app.got_subcommand(paper_cmd)) return cli::paper(paper);
      if (app.got_subcommand(beyond_cmd)) return cli::beyond(beyond);
      if (app.got_subcommand(sweep_cmd)) return cli::sweep(sweep);
      if (app.got_subcommand(report_cmd)) {
        fmt::print("report: {}\n", write_report(report));
        return 0;
      }
      return 0;
    };
    const int rc = run();
    // What was printed must have been written (a full disk, a closed pipe).
    check_stdout();
    return rc;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "oovr: error: %s\n", printable(e.what(), true).c_str());
    return 2;
  } catch (const Error& e) {
    std::fprintf(stderr, "oovr: error: %s\n", printable(e.what(), true).c_str());
    return 1;
  } catch (const std::system_error& e) {
    // fmt::print's failure on a full device or a closed pipe.
    const std::string what = e.what();
    if (what.rfind("cannot write to file", 0) == 0)
      std::fprintf(stderr, "oovr: error: cannot write to standard output: %s\n", e.code().message().c_str());
    else std::fprintf(stderr, "oovr: error: %s\n", printable(e.what(), true).c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    // Readers bound what an input may ask for (docs/reliability.md); what
    // still does not fit is named by the inputs of the run.
    const std::string message = out_of_memory_message(std::string("running '") + (argc > 1 ? argv[1] : "oovr") + "'");
    std::fprintf(stderr, "oovr: error: %s (a scene, resolution or --frames too large for this machine)\n", message.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oovr: error: %s\n", printable(e.what(), true).c_str());
    return 1;
  }
  return 0;
}
