// The paper's evaluation (`oovr paper`): the sweep experiments/paper.toml
// (every scheme on every scene at the paper's resolutions for Figures 15
// and 16, the link bandwidth sweep of Figure 17, the GPM count sweep of
// Figure 18, OO-VR's ablations, the SMP comparison, the model's earlier
// steps and the one-pass workloads) runs into a results database; the
// runs are read back from it and the claims P1-P18 of the paper (their
// values from experiments/paper-claims.toml, claims.h) set beside oovr's,
// per scene, with the reasons where they differ (docs/paper-comparison.md),
// plus CSV, JSON and SVG plots.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct PaperOptions {
  // The evaluation: a resolved sweep (experiments/paper.toml, which oovr
  // carries: paper_sweep()), run into the database `db`.
  Sweep sweep;
  Config machine;  // the machine the sweep's points start from (load_evaluation, resolve_on_machine)
  // Where each key the machine sets came from ("FILE.toml:LINE", "--set",
  // "FILE [set]"): for the document's account of the machine.
  std::map<std::string, std::string> machine_sources;
  std::string db;                        // the results database (created; points it holds are not run again)
  std::vector<std::string> only_scenes;  // run and report these scenes only (and their one-pass forms); empty: all
  unsigned jobs = 0;                     // points at once (0: every core)
  std::string command;                   // as run, for the document
  std::function<void(const std::string&)> progress;
  std::function<void(size_t)> on_plan;              // how many points will run (the others are in the database)
  std::function<void(const RunRecord&)> on_record;  // each point as it ends (a progress display)

  // Derived from the runs by run_paper, for the writers: the resolutions of
  // Figure 15, the one of the sweeps and ablations (the one the link sweep
  // ran at), the frames each run measured from `first_frame`, the filtering,
  // whether the model's earlier steps, OO-VR's copy capacities and the
  // one-pass workloads ran.
  std::vector<std::string> resolutions;
  std::string sweep_resolution;
  int first_frame = 0;
  int frames = 0;
  int aniso = 16;
  bool steps = false;
  bool copies = false;
  bool workloads = false;
  MachineSpec spec;  // the machine as the document describes it: `machine`, read once
};

// One run: `variant` names the overrides on top of the machine ("" for none).
struct PaperRun {
  std::string scene, resolution, scheme, variant;
  SchemeResult result;
};

// What a scene is, for the explanations (its first frame at the sweep
// resolution).
struct PaperSceneStats {
  size_t draws = 0;
  uint64_t triangles = 0;
  uint64_t texture_bytes = 0;
  double vertex_share = 0;  // vertex instructions over all shader instructions
};

struct PaperResults {
  std::vector<std::string> scenes;  // measured, in order
  // Scenes also measured as one-pass workloads (their runs are under
  // one_pass_scene(name), at the sweep resolution only).
  std::vector<std::string> one_pass_scenes;
  std::map<std::string, PaperSceneStats> stats;
  std::vector<std::string> skipped;  // "scene: reason"
  std::vector<PaperRun> runs;        // `variant`: the run's settings that differ from the machine, canonical
  std::vector<RunRecord> records;    // the same runs as stored (without their images): what the claims are measured on
  double seconds = 0;
  size_t ran = 0;  // points run now (the others were in the database)
  // The run of `scheme` on `scene` at `resolution` with the settings
  // `variant` ("key=value;..." as --set takes them, in any order and
  // spelling: "link.bandwidth=1TBps" finds the run stored with 1e12).
  const SchemeResult* find(const std::string& scene, const std::string& resolution, const std::string& scheme,
                           const std::string& variant = "") const;

  Config machine;
  std::map<std::string, size_t> index;                   // "scene|resolution|scheme|canonical variant" -> runs
  mutable std::map<std::string, std::string> canonical;  // asked variant -> canonical
};

// The evaluation oovr carries (experiments/paper.toml): its text, and read.
std::string paper_sweep_text();
Sweep paper_sweep();

// An evaluation's sweep on a machine, into o.sweep, o.machine and
// o.machine_sources: the sweep file's `text` (named `name`, its paths
// relative to `base_dir`) with the machine `preset` and `settings` give
// written into its [set] (sweep_on_machine: the file's own [set] is the
// machine too; `frames`, when not 0, every point's window), every point resolved on that machine with its own settings
// on top (resolve_on_machine), points that are the same run shared. Throws
// Error naming a bad preset, setting or point.
void load_evaluation(PaperOptions& o, const std::string& text, const std::string& name, const std::string& base_dir,
                     const std::string& preset = "", const std::vector<std::string>& settings = {}, int frames = 0);

// A key of a machine that differs from oovr's default (the paper's Table 1).
struct MachineChange {
  std::string key, value, fallback, source;
};
// The keys `machine` sets to another value than the default, by key, with
// their sources (`sources`' label where it has one).
std::vector<MachineChange> machine_changes(const Config& machine, const std::map<std::string, std::string>& sources = {});

// Runs the points of o.sweep (those of o.only_scenes) the database does
// not hold, then reads every one of them back from it, fills o's derived
// fields and the scenes' statistics. Throws Error when no scene could be
// run.
PaperResults run_paper(PaperOptions& options);

// Writes results.json, one CSV per figure and the SVG plots into `dir`.
void write_paper_outputs(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// The SVG plots of Figures 15 to 18 alone.
void write_paper_plots(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// The machine of the sweep `sweep_name` in the results database `other_db`
// (its definition's preset and [set]), the database checked whole first:
// what `oovr paper --against` reads before it runs anything. Throws Error
// naming the database when it cannot be read, fails its check or holds no
// such sweep.
Config paper_against_machine(const std::string& other_db, const std::string& sweep_name);
// Writes the paper's claims measured on two machines side by side
// (`oovr paper --against`): this evaluation's (r, o) and the one in the
// results database `other_db` (another `oovr paper --out`: its sweep of the
// same name), on `other_machine` (paper_against_machine's), at o's claims'
// resolution over the scenes both ran, as paper-against.md and
// claims-against.csv in `dir`. Throws Error naming the database when it
// has no scene in common.
void write_paper_against(const PaperResults& r, const PaperOptions& o, const std::string& other_db, const Config& other_machine,
                         const std::string& dir);

// Writes the comparison document; `plots_dir` (may be empty) is linked
// relative to the document.
void write_paper_doc(const PaperResults& results, const PaperOptions& options, const std::string& path,
                     const std::string& plots_dir);

}  // namespace oovr
