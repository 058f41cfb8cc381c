// Results as text: what `oovr simulate` and `oovr compare` print, written
// once for the CLI and the Python module (whose results print the same).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "oovr/run/simulation.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

// One row of `oovr compare`'s table. Ratios are against the baseline's run
// and NaN when the baseline was not among the schemes (or, for traffic,
// moved no bytes).
struct ComparisonRow {
  std::string scheme;
  double latency_ms = 0;          // one frame, first command to last pixel (mean over the frames)
  double speedup = NAN;           // the baseline's latency over the scheme's
  double frames_per_s = 0;        // throughput, frames in flight overlapping
  double throughput_ratio = NAN;  // over the baseline's
  double inter_gpm_mb = 0;        // bytes moved between GPMs per frame, in 10^6 bytes
  double traffic_ratio = NAN;     // over the baseline's
  double best_to_worst = 0;       // busiest GPM's busy time over the least busy one's
  double energy_mj = NAN;         // the memory system's energy per frame (energy_of), NaN when not counted
};
std::vector<ComparisonRow> comparison_rows(const std::vector<SchemeResult>& results);

// "frames 0 to 3" or "frame 7".
std::string frame_range(int first, int frames);

// `oovr compare`'s heading line and table (no trailing timing line).
std::string comparison_text(const Simulation& s);

// `oovr simulate`'s heading line and figures for the simulation's result
// `i` (no trailing timing line).
std::string simulation_text(const Simulation& s, size_t i = 0);

// "  time: traces 270 ms (4 of 4 from the cache), simulation 180 ms", then
// the trace notes, one "  note:" line each.
std::string timing_text(const Simulation& s);

}  // namespace oovr
