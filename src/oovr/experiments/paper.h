// The paper's evaluation as one sweep over replayed traces (`oovr paper`):
// every scheme on every scene at the paper's resolutions (Figures 15 and
// 16), the link bandwidth sweep (Figure 17), the GPM count sweep (Figure
// 18), OO-VR's ablations and the SMP comparison; then the claims P1-P16 of
// the paper (its values in the document's tables) beside oovr's, per scene, with the reasons
// where they differ (docs/paper-comparison.md), plus CSV, JSON and SVG plots.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct PaperOptions {
  // Scenes; the default list is the built-in scenes and the game levels of
  // the workloads page, those not installed being left out (and said so).
  std::vector<std::string> scenes;
  std::vector<std::string> resolutions = {"640x480", "1280x1024", "1600x1200"};
  std::string sweep_resolution = "1280x1024";  // of the sweeps and ablations
  int first_frame = 0;
  int frames = 4;
  int aniso = 16;
  // Also run the claims with issue 9's model changes switched on one by one
  // (the document's before-and-after table).
  bool steps = true;
  // Also run the game levels as one-pass workloads (paper_figures.h), for
  // the document's workload section.
  bool workloads = true;
  Config config;        // the machine: preset and --set overrides
  std::string command;  // as run, for the document
  std::function<void(const std::string&)> progress;
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
  std::vector<PaperRun> runs;
  double seconds = 0;
  const SchemeResult* find(const std::string& scene, const std::string& resolution, const std::string& scheme,
                           const std::string& variant = "") const;
};

// The default scenes of the evaluation.
std::vector<std::string> paper_default_scenes();

PaperResults run_paper(const PaperOptions& options);

// Writes results.json, one CSV per figure and the SVG plots into `dir`.
void write_paper_outputs(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// The SVG plots of Figures 15 to 18 alone.
void write_paper_plots(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// Writes the comparison document; `plots_dir` (may be empty) is linked
// relative to the document.
void write_paper_doc(const PaperResults& results, const PaperOptions& options, const std::string& path,
                     const std::string& plots_dir);

}  // namespace oovr
