// The study beyond the paper (`oovr beyond`): the sweep experiments/
// beyond.toml (the schemes the field uses besides the paper's, with the
// baseline, OO-VR and oovr's own OO-VR with screen affinity, on the
// built-in scenes, game levels and captured game frames, 2 to 16 GPMs,
// 32 GB/s to 1 TB/s links) runs into a results database as the paper's
// evaluation does (run_paper), and docs/beyond-paper.md is written from it:
// speed-up over one GPM against the GPM count and against link bandwidth,
// traffic by category, balance, and GPUpd's and CHOPIN's standing against
// their published ratios, with why oovr's differ. Every number in it is
// computed from the runs; the published ones are the papers'.
#pragma once

#include <string>

#include "oovr/experiments/paper.h"
#include "oovr/experiments/sweep.h"

namespace oovr {

// The study oovr carries (experiments/beyond.toml), read.
Sweep beyond_sweep();
std::string beyond_sweep_text();  // its text

// runs.csv (every run: scene, scheme, settings, latency, speed-ups, traffic
// by category, balance) and the plots, into `dir`.
void write_beyond_outputs(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// The SVG plots alone.
void write_beyond_plots(const PaperResults& results, const PaperOptions& options, const std::string& dir);
// The document; `plots_dir` (may be empty) is linked relative to it.
void write_beyond_doc(const PaperResults& results, const PaperOptions& options, const std::string& path,
                      const std::string& plots_dir);

}  // namespace oovr
