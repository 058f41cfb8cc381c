// One memory replay shared by runs that differ only in timing (issue 31;
// docs/performance.md, "Sharing a memory replay").
//
// The memory system sees addresses, never time: two runs of a scheme whose
// machines differ only in link or DRAM bandwidth and latency, cache
// latencies, the GPMs' clock and throughputs or the timing model's switches
// make the same calls on it and get the same answers, as long as the
// scheme's distribution does not depend on timing. So the first such run
// records every answer (each unit's traffic, each copy's bytes, each frame's
// totals and statistics) on a tape, and the others play the tape back
// instead of walking the caches line by line; their timing is run in full.
//
// Nothing is assumed about the scheme: every call's arguments are folded
// into a running hash, which the tape stores beside each answer and the
// player checks. A run whose calls differ from the recording's (OO-VR's
// runtime sends objects where the timing says, so its calls follow the
// timing) is stopped at the first difference with TapeMismatch and run
// again in full (run_scheme_window does that), so a played run's results
// are the results of running it, bit for bit.
#pragma once

#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "oovr/core/stats.h"
#include "oovr/memory/memory_system.h"

namespace oovr {

// A played run's calls differ from the recorded ones (or the run asked the
// memory system something the tape does not hold).
class TapeMismatch : public std::exception {
 public:
  explicit TapeMismatch(std::string why) : m_why(std::move(why)) {}
  const char* what() const noexcept override { return m_why.c_str(); }

 private:
  std::string m_why;
};

class MemoryTape {
 public:
  // What FrameSim::finish reads of the memory system at a frame's end: the
  // frame's traffic, the footprint and the memory system's statistics
  // since the frame began; per tile, the inter-GPM bytes of the records
  // replayed for the run's first frame.
  struct FrameEnd {
    PerCategory inter_gpm_bytes{};
    uint64_t local_dram_bytes = 0;
    uint64_t footprint_bytes = 0;
    Stats stats;
    std::vector<uint64_t> tile_inter_gpm_bytes;
  };

  // Made for runs with this shared_replay_key (schemes/i_scheme.h): the
  // scheme and the machine as the memory system sees it. A run with
  // another key is not played from it.
  explicit MemoryTape(std::string key) : m_key(std::move(key)) {}
  const std::string& key() const { return m_key; }

  // Recording, in call order; `calls` is the running hash of the calls so
  // far (their arguments), this answer's included.
  void traffic(uint64_t calls, const UnitTraffic& t);
  void value(uint64_t calls, uint64_t v);
  void frame_end(uint64_t calls, FrameEnd e);

  // The bytes the tape holds (answers and frame ends, roughly).
  uint64_t bytes() const;
  size_t answers() const { return m_index.size(); }

  // Reads a tape back in order, checking each answer's hash.
  class Player {
   public:
    explicit Player(std::shared_ptr<const MemoryTape> tape) : m_tape(std::move(tape)) {}
    // The next answer, which must be of this kind with this hash; throws
    // TapeMismatch otherwise. `t` is shaped for the machine (reset).
    void traffic(uint64_t calls, UnitTraffic& t);
    uint64_t value(uint64_t calls);
    const FrameEnd& frame_end(uint64_t calls);
    // Whether every answer was read (a run that made fewer calls than the
    // recording differs from it too).
    bool at_end() const { return m_next == m_tape->m_index.size(); }

   private:
    size_t take(uint64_t calls, uint8_t kind);
    std::shared_ptr<const MemoryTape> m_tape;
    size_t m_next = 0;
  };

 private:
  enum Kind : uint8_t { kTraffic, kValue, kFrameEnd };
  struct Answer {
    uint64_t calls;
    uint64_t at;  // where its words start (traffic, value) or its frame end
    uint8_t kind;
  };
  std::string m_key;
  std::vector<Answer> m_index;
  // Traffic, sparse: a count of words, then per field that is not zero one
  // word of its index (16 bits) and value (48 bits), or the index with the
  // top bit set and the value in the next word when it needs more.
  std::vector<uint64_t> m_words;
  std::vector<FrameEnd> m_frames;
};

}  // namespace oovr
