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

// Every figure of `r`, in a fixed order. Bytes and counts are per frame
// (the window's mean); "utilisation" of a link is its bytes per frame at
// the run's frame rate over the link's bandwidth.
std::vector<Metric> metrics_of(const SchemeResult& r);

}  // namespace oovr
