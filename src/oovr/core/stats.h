// Statistics (DESIGN.md: core owns them). Each is a figure at a location
// (`memory`, `gpm[2].dram`, `link[0->1]`, a scheme's name), with a name, a
// unit and the rule a window of frames merges it by. Their owners register
// them where they count them, one line each (MemorySystem::report,
// TimingEngine::report, a scheme's own figures), in the spirit of gem5's
// ADD_STAT and Ramulator 2's Stats; every export (the database's metrics
// rows, JSON, Python, the text table, the paper and the report) reads them
// from here (run/result_metrics.h). Derived numbers (shares,
// utilisation) are formulas evaluated at output time, never accumulated.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace oovr {

// How the runs of a window (experiments' frames, run in sequence) merge.
enum class Merge : uint8_t {
  sum,   // counted over the work (bytes, accesses): a window reports its total per frame
  mean,  // a time, rate or ratio of one run: a window reports the mean over the runs that report it
  max,   // a size or peak: a window reports the largest
};
const char* merge_name(Merge m);

struct Stat {
  std::string location;  // "memory", "gpm[2].dram", "link[0->1]", "oo-vr"
  std::string name;      // "accesses", "bytes"
  std::string unit;      // base unit ("B", "s", "B/s") or "" for counts and ratios
  Merge merge = Merge::mean;
  // A count of whole things: a window's per-frame figure rounds to nearest.
  bool whole = false;
  double value = 0;
};

// An owner's statistics in the order they were registered; a location and
// name appear once.
class Stats {
 public:
  // Registers a statistic. Throws Error when the location already has one
  // of that name (each has one owner) or the value is not finite.
  void add(std::string location, std::string name, double value, std::string unit = "", Merge merge = Merge::mean);
  // A count of whole things (Merge::sum, whole): values below 2^53, exact.
  void count(std::string location, std::string name, uint64_t value, std::string unit = "");
  // Appends another owner's statistics (the same checks as add).
  void append(const Stats& other);

  const std::vector<Stat>& all() const { return m_stats; }
  size_t size() const { return m_stats.size(); }
  bool empty() const { return m_stats.empty(); }
  // The statistic, or null when none is registered there.
  const Stat* find(const std::string& location, const std::string& name) const;
  // Its value; throws Error naming it when there is none.
  double at(const std::string& location, const std::string& name) const;

  // Counters run on from frame to frame (the memory system's); a frame's
  // are the difference of two snapshots of the same owner (ChampSim's
  // cache_stats): summed statistics subtract `before`, the others keep
  // their value now. Throws Error when the snapshots do not match.
  Stats since(const Stats& before) const;
  // A window's statistics from its runs' (covering `frames` frames in all),
  // each by its rule, in order of first appearance: sums are totals over
  // the runs divided by `frames` (whole ones rounded to nearest), means
  // over the runs that report the statistic, maxima the largest.
  static Stats window(const std::vector<const Stats*>& runs, uint64_t frames);

 private:
  std::vector<Stat> m_stats;
};

}  // namespace oovr
