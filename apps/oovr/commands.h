// The CLI's commands that replay traces through schemes (simulate.cpp),
// sweep, paper, correlate and check captures (capture.cpp).
#pragma once

#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/core/text.h"

namespace oovr::cli {

struct SimulateArgs {
  std::string scene;
  std::string scheme;
  int frame = 0;
  int frames = 0;  // 0: one per GPM
  std::string resolution = "1280x1024";
  std::string eye_resolution;
  int aniso = 16;
  std::string config;
  std::vector<std::string> settings;
  std::string json, gpm_image, traffic_image;
  std::string timeline;                // Trace Event Format JSON of every unit (oovr simulate --timeline)
  size_t timeline_events = 1'000'000;  // at most this many units in it
  bool no_cache = false;
  std::string command;  // the command line, for the results
};

struct PaperArgs {
  std::string sweep;   // the evaluation's sweep file; "": the one oovr carries (experiments/paper.toml)
  std::string scenes;  // comma-separated: only these scenes of the sweep; empty: all
  std::string out = "out/paper";
  std::string doc;      // also write the comparison here (docs/paper-comparison.md); empty: only into --out
  bool resume = false;  // keep the database in --out and run only the points it lacks
  unsigned jobs = 0;
  std::string config;                 // the machine's preset (--config); empty: the sweep's, else Table 1
  std::vector<std::string> settings;  // the machine's keys (--set key=value), on top of the preset
  int frames = 0;                     // every point's window (--frames); 0: the sweep file's
  std::string against;                // another evaluation's database, its claims set beside these (paper only)
  std::string command;                // the command line, for the document
};

struct CorrelateArgs {
  std::string hardware;  // CSV of measured frames
  std::string scheme = "single-gpm";
  std::string config;
  std::vector<std::string> settings;
  std::string json;
  bool per_frame = false;
  bool no_cache = false;
  double min_r = -2;      // fail below (-2: no check)
  double max_spread = 0;  // fail above (0: no check)
  std::string sweep;      // "key=v1,v2,...": correlate at each value, pick the most proportional
  std::string command;    // the command line, for the results
};

struct SweepArgs {
  std::string file;                   // the sweep definition
  std::vector<std::string> settings;  // --set: overrides of the file's [set] (sweep_with_settings)
  std::string db;                     // "": FILE's stem + ".db" in the current folder
  bool resume = false;
  bool retry_failed = false;
  bool reconcile = false;  // the database holds this sweep from an edited file: keep what the file still has
  unsigned jobs = 0;       // points at once (0: every core)
  std::string backend = "local";
  bool no_cache = false;
  bool collect = false;
  bool list = false;      // print the points and their ids, run nothing
  int task = -1;          // >= 0: run this task of --slurm-dir (what the job script runs)
  std::string slurm_dir;  // "": the database's path + ".slurm"
  std::string partition, time_limit;
  int array_limit = 0, chunk = 0, cpus_per_task = 1;
  bool wait = false;
  std::vector<std::string> sbatch_args;
  std::string command;
};

struct CheckCaptureArgs {
  std::string scene;      // a captured game
  std::string snapshots;  // glretrace's snapshots of it, or
  std::string against;    // the scene that was captured (the round trip)
  std::string images;     // write oovr's image of each frame here
  double min_psnr = 40;
  int min_frames = 20;              // with --snapshots
  double max_fragment_diff = 0.01;  // with --against: percent, per frame
};

// A preset (or the built-in defaults) with --set overrides.
Config machine_config(const std::string& file, const std::vector<std::string>& settings);
int simulate(const SimulateArgs& a);
int compare(const SimulateArgs& a, const std::vector<std::string>& schemes);
int paper(const PaperArgs& a);
int beyond(const PaperArgs& a);  // the same arguments; --out defaults to out/beyond
int correlate(const CorrelateArgs& a);
int sweep(const SweepArgs& a);
int check_capture(const CheckCaptureArgs& a);  // capture.cpp

}  // namespace oovr::cli
