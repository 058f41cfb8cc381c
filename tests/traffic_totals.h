// A memory system's running totals as one comparable and printable value,
// for tests that compare two memory systems fed the same accesses.
#pragma once

#include <tuple>

#include "oovr/memory/memory_system.h"

namespace oovr::test {

inline auto traffic_totals(const TrafficTotals& t) {
  return std::make_tuple(t.accesses, t.l1_hits, t.l2_hits, t.remote_hits, t.home_l2_hits, t.dram_lines, t.l1_lookups,
                         t.l2_lookups, t.remote_lookups, t.link_bytes, t.dram_read_bytes, t.dram_write_bytes, t.inter_gpm_bytes,
                         t.delivered, t.moved);
}

}  // namespace oovr::test
