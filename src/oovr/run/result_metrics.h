// A run's figures in long form, one row per (location, metric): what the
// results database stores (docs/results.md, "The results database") and
// the report and queries read. Locations name where a figure was measured:
// "frame", "gpm[2]", "gpm[2].dram", "l2", "link[0->1]", "gpm[0]->gpm[1]",
// or the scheme's own name for its figures (OO-VR's batches, moved chunks
// and predictor rates).
#pragma once

#include <string>
#include <vector>

#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct Metric {
  std::string location;
  std::string metric;
  double value = 0;
  std::string unit;  // "s", "B", "cycles", "frames/s", "bit"; "" for counts and ratios
};

// Every figure of `r`: the frame's (latency, throughput, traffic, busy
// time), then every statistic (r.stats, core/stats.h) in the order its
// owners registered it, with the formulas evaluated at output time: after
// each level's reads `served`, its `served_share` of the accesses; after
// each resource's `capacity`, its `utilisation` (utilisation_of); after
// each energy figure (`energy_per_lookup`, `energy_per_bit`), the
// location's `energy` (energy_at), and on the frame its total `energy`
// and its parts (`energy.caches`, `energy.dram`, `energy.links`). Bytes,
// counts and energies are per frame (the window's mean).
std::vector<Metric> metrics_of(const SchemeResult& r);
// Whether a row of metrics_of is one of the run's statistics, not a figure
// of the frame (location "frame" or "frame[k]", a GPM's "busy") or a
// formula (`served_share`, `utilisation`): the rows a stored result's
// statistics are read back from (scheme_result_from_stored).
bool is_stat_row(const Metric& m);

// The memory system's energy per frame (docs/model.md, "Energy"), each
// location's integrated from what it counted: a cache's lookups times its
// energy_per_lookup, a DRAM's or link's bytes times 8 times its
// energy_per_bit. Not the SMs' arithmetic: what moving data costs, where
// the schemes differ. All zero, and `known` false, for a result stored
// before oovr counted energy.
struct Energy {
  double caches = 0, dram = 0, links = 0;  // J per frame
  bool known = false;
  double total() const { return caches + dram + links; }
};
Energy energy_of(const SchemeResult& r);
// A location's energy per frame (J), or NaN when it has no energy figure.
double energy_at(const SchemeResult& r, const std::string& location);

// A resource's use per frame at the run's frame rate over its capacity:
// of a link or a DRAM, the bytes the memory system counted (exact) at the
// location; of another resource, the amount the timing engine used. NaN
// when the location has no capacity; a utilisation read back from a
// result written before the engine reported capacities (results.md) is
// returned as it was stored.
double utilisation_of(const SchemeResult& r, const std::string& location);

// "link[0->1]" -> "gpm0->gpm1", "link[2->switch0]" -> "gpm2->switch0": the
// topology's name of the link at a statistics location (JSON's `links`).
std::string link_name_at(const std::string& location);
// Its inverse: the statistics location of a link the topology names
// ("gpm0->gpm1" -> "link[0->1]"); empty for a name without "->".
std::string link_location_of(const std::string& name);

}  // namespace oovr
