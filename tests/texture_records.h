// Random records of texture reads, for the tests of the repeat filter
// (FrameTrace::tex_lines_without_repeats) and of the caches it feeds: reads
// that re-read the read before, cycle among a few lines of one set (a
// material's layers alternating in one set, what the LRU rule is for), or
// read a line of any set.
#pragma once

#include <cstdint>

#include "oovr/core/rng.h"
#include "oovr/pipeline/frame_trace.h"

namespace oovr::test {

struct RandomRecords {
  int records = 0;
  uint64_t sets = 4;                // a line's set: its index modulo this
  uint32_t fewest = 0, spread = 1;  // a record reads fewest + [0, spread) lines
  uint32_t repeats_in_ten = 5;      // a read re-reads the one before in this many of ten
  uint32_t widths = 5;              // a cycle is among 2 + [0, widths) lines of one set
  uint32_t textures = 2;
  uint32_t any_lines = 40;  // one read in ten: line [0, any_lines) of any texture
};

// Appends the records to `trace` (its records and lines), drawing from `rng`.
inline void add_random_records(FrameTrace& trace, Rng& rng, const RandomRecords& r) {
  for (int k = 0; k < r.records; ++k) {
    TileWork t;
    t.tex_begin = trace.tex_lines.size();
    const uint32_t n = r.fewest + rng.below(r.spread);
    const uint32_t set = rng.below(uint32_t(r.sets)), width = 2 + rng.below(r.widths), texture = rng.below(r.textures);
    TexLine previous = make_tex_line(0, 0);
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t how = rng.below(10);
      const TexLine l = how < r.repeats_in_ten ? previous
                        : how < 9              ? make_tex_line(texture, set + uint32_t(r.sets) * rng.below(width))
                                               : make_tex_line(rng.below(r.textures), rng.below(r.any_lines));
      trace.tex_lines.push_back(l);
      previous = l;
    }
    t.tex_count = n;
    trace.tiles.push_back(t);
  }
}

}  // namespace oovr::test
