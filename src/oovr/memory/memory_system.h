// The NUMA multi-GPM memory system (DESIGN.md, "How work becomes time"):
// turns "GPM g touches these lines for work unit u" into cache hits, DRAM
// bytes per GPM and bytes per link.
//
// Path of a line access by SM s of GPM g:
//   shader reads (vertex, index, texture) -> L1 of (g, s)
//   data homed on g (or copied to g) -> L2 of g -> DRAM of g
//   data homed elsewhere, reads -> remote cache of g (MCM-GPU's L1.5)
//       -> link route home -> g -> L2 of the home -> DRAM of the home
//   data homed elsewhere, writes (ROP colour/depth) -> route g -> home ->
//       L2 of the home (write-through; g's remote-cache copy is dropped)
// L2s are memory-side caches of their GPM's DRAM, write-back and
// write-allocate (a write miss does not read DRAM: ROPs write whole sectors).
// Nothing here knows about schemes or time: timing converts the bytes and
// hits returned per work unit into cycles.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "oovr/core/stats.h"
#include "oovr/memory/address_map.h"
#include "oovr/memory/cache.h"
#include "oovr/memory/category.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/memory/placement/i_placement.h"
#include "oovr/memory/topology/i_topology.h"

namespace oovr {

struct LineAccess {
  uint64_t address = 0;  // any byte of the line
  Category category = Category::texture;
  bool write = false;
};

using PerCategory = std::array<uint64_t, kCategories>;

// A record's framebuffer lines (FrameSim::replay): bit l of a mask names line
// l of the tile, at `depth` or `colour` + l * the line's bytes; the lines are
// accessed line by line, each as depth read, colour read, depth write,
// colour write.
struct TileLines {
  uint64_t depth = 0, colour = 0;  // the tiles' first lines' addresses
  uint32_t depth_read = 0, colour_read = 0, depth_write = 0, colour_write = 0;
};

// What one work unit's accesses cost: the answer of the narrow interface.
struct UnitTraffic {
  uint64_t accesses = 0;
  uint64_t l1_hits = 0;       // in the requesting SM's L1
  uint64_t l2_hits = 0;       // local data, in the requester's L2 (reads and writes)
  uint64_t remote_hits = 0;   // remote data, in the requester's remote cache
  uint64_t home_l2_hits = 0;  // remote data, in its home's L2
  uint64_t dram_lines = 0;    // lines read from a DRAM (local or remote)
  // Where each read was served, for its latency (writes are posted: they
  // cost bandwidth, not latency): L1 hits, remote-cache hits and home-L2
  // hits above are reads; these are the rest.
  uint64_t l2_read_hits = 0;                                // local reads served by the requester's L2
  uint64_t local_dram_reads = 0;                            // local reads served by its DRAM
  uint64_t remote_dram_reads = 0;                           // remote reads served by the holder's DRAM
  uint64_t remote_hops = 0;                                 // link hops of remote reads, summed over the reads
  std::vector<uint64_t> dram_read_bytes, dram_write_bytes;  // per GPM
  std::vector<uint64_t> link_bytes;                         // per link
  PerCategory inter_gpm_bytes{};                            // bytes moved between GPMs, once per transfer however many hops

  void reset(int gpms, int links);
  // Adds another unit's (or record's) costs; both shaped for one machine.
  UnitTraffic& operator+=(const UnitTraffic& o);
  uint64_t total_link_bytes() const;
  uint64_t total_inter_gpm_bytes() const;
};

// Running totals of everything, broken down by category.
struct TrafficTotals {
  std::vector<PerCategory> link_bytes;        // [link][category]
  std::vector<PerCategory> dram_read_bytes;   // [gpm][category]
  std::vector<PerCategory> dram_write_bytes;  // [gpm][category]
  PerCategory inter_gpm_bytes{};
  // delivered[src * gpms + dst]: bytes of data held by GPM src (its L2 or
  // DRAM) delivered to requester dst; used to check conservation.
  std::vector<uint64_t> delivered;
  // moved[from * gpms + to]: bytes sent from GPM `from` to GPM `to` over the
  // links (every category, counted once however many hops): the GPM-to-GPM
  // traffic matrix.
  std::vector<uint64_t> moved;
  uint64_t accesses = 0, l1_hits = 0, l2_hits = 0, remote_hits = 0, home_l2_hits = 0, dram_lines = 0;
  // Lookups in each level's arrays, hits and misses alike (the energy they
  // take): the L2s count their own GPM's accesses and those they serve for
  // others (reads a remote cache missed, writes through to the home).
  uint64_t l1_lookups = 0, l2_lookups = 0, remote_lookups = 0;
  uint64_t copies_evicted = 0;  // pre-allocated pages dropped to make room for others
  uint64_t copies_refused = 0;  // pages not copied: their GPM's room was taken by the same batch
};

class MemorySystem {
 public:
  // The address map must hold every region before the memory system is
  // built: its page tables cover the map as it is then.
  // Throws Error, before allocating, when its state (state_bytes) is more
  // than this process may still use (core/host.h, check_memory_room).
  MemorySystem(const MemorySpec& spec, const AddressMap& map);
  // The bytes of a memory system's caches' tags and pages' state.
  static uint64_t state_bytes(const MemorySpec& spec, const AddressMap& map);
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;

  const MemorySpec& spec() const { return m_spec; }
  const Topology& topology() const { return *m_topology; }
  const AddressMap& address_map() const { return m_map; }

  // GPM `gpm`, SM `sm` performs `lines` for one work unit. The unit's costs
  // are added to `out` (reset it per unit) and to the totals. `l1_repeats`
  // texture reads of the unit were left out of `lines` as L1 hits that
  // leave the L1 as reading them would (FrameSim::replay, the rules of
  // FrameTrace::tex_lines_without_repeats): each is counted as the hit it is.
  void access(int gpm, int sm, std::span<const LineAccess> lines, UnitTraffic& out, uint64_t l1_repeats = 0);
  // The same for a record's texture reads, as the trace lists them (each at
  // layout.texture_line), followed by its framebuffer lines: the replay's
  // accesses without a copy of every address in between (FrameSim::replay).
  void access(int gpm, int sm, const SceneLayout& layout, std::span<const TexLine> texture_reads, const TileLines& tile,
              UnitTraffic& out, uint64_t l1_repeats);
  // The same with the framebuffer's lines listed one by one (the tests'
  // records replayed by hand).
  void access(int gpm, int sm, const SceneLayout& layout, std::span<const TexLine> texture_reads,
              std::span<const LineAccess> lines, UnitTraffic& out, uint64_t l1_repeats);
  // Every SM's L1 has the same sets: a line's is (address / line) & this.
  uint64_t l1_set_mask() const { return m_l1.front().set_mask(); }

  // Copies the pages of [address, address + bytes) into GPM `gpm`'s DRAM
  // ahead of use, as whole pages, from their homes; pages already held by
  // `gpm` are not copied again; untouched pages are placed on `gpm`. The
  // copy's bytes are link traffic of category prealloc. Copies live in
  // what the GPM's homes leave free of its DRAM (MemorySpec::dram_capacity,
  // capped by copy_capacity when it is set) and persist across frames while
  // they fit: to make room, the least recently used (or oldest) copies are
  // dropped, never one of the current batch (since begin_batch()); a page
  // that finds no room is not copied (copies_refused). Returns bytes copied.
  uint64_t preallocate(uint64_t address, uint64_t bytes, int gpm, UnitTraffic& out);
  // Starts a batch of pre-allocations: what it copies is kept until the
  // next batch begins.
  void begin_batch() { m_batch_start = ++m_clock; }
  // Bytes of copies each GPM holds now, and the most it has held.
  uint64_t copy_bytes(int gpm) const { return m_copy_bytes[size_t(gpm)]; }
  uint64_t copy_peak_bytes(int gpm) const { return m_copy_peak[size_t(gpm)]; }
  // Bytes each GPM's DRAM holds as the home (or, replicated, a replica) of
  // its pages: what copies cannot use.
  uint64_t homed_bytes(int gpm) const { return m_homed_bytes[size_t(gpm)]; }
  // Moves `bytes` from GPM `from` to GPM `to` (composition, commands):
  // counted on every link of the route and once as inter-GPM traffic.
  void transfer(int from, int to, uint64_t bytes, Category category, UnitTraffic& out);

  // Names a region's home (pinned placement only).
  void pin(uint32_t region, int gpm);
  // Makes `gpm` the home of the page holding `address` if nobody has
  // touched it yet (a buffer the application maps into a GPM's DRAM, as a
  // sort-last scheme maps its final frame); returns whether it did.
  bool place(uint64_t address, int gpm);
  // Boundaries at which the remote caches are invalidated (per the spec):
  // GPM `gpm` finished a draw (-1: every GPM did), the frame ended.
  void end_draw(int gpm = -1);
  void end_frame();

  // -1 when nobody touched the page yet (or the address is past the map).
  int home_of(uint64_t address) const {
    const uint64_t page = address / m_page_bytes;
    return page < m_home.size() ? m_home[page] : -1;
  }
  bool holds(int gpm, uint64_t address) const;
  // Data bytes resident in each GPM's DRAM (homes and copies; the used part
  // of each page).
  std::vector<uint64_t> resident_bytes() const;
  uint64_t footprint_bytes() const;

  const TrafficTotals& totals() const { return m_totals; }
  // Registers the memory system's counters, running totals since it was
  // built (a frame's are the difference of two snapshots, Stats::since):
  // `memory` accesses; the reads each level served (`l1`, `l2`,
  // `remote_cache`, `home_l2`, `dram`); each GPM's DRAM bytes
  // (`gpm[g].dram`); each link's bytes, every hop counted
  // (`link[0->1]`); the GPM-to-GPM matrix, once per transfer
  // (`gpm[0]->gpm[1]`); copies dropped for room and refused for want of it.
  void report(Stats& out) const;
  const Cache& l1(int gpm, int sm) const { return m_l1[size_t(gpm * m_spec.sms_per_gpm + sm)]; }
  const Cache& l2(int gpm) const { return m_l2[size_t(gpm)]; }
  const Cache& remote_cache(int gpm) const { return m_remote[size_t(gpm)]; }

 private:
  // Both access()es: the texture reads at `layout` (none without one),
  // then `lines`, then the tile's lines.
  void access_lines(int gpm, int sm, const SceneLayout* layout, std::span<const TexLine> texture_reads,
                    std::span<const LineAccess> lines, const TileLines& tile, UnitTraffic& out, uint64_t l1_repeats);
  int home(uint64_t page, int requester) {
    const int h = m_home[page];
    return h >= 0 ? h : place_first(page, requester);
  }
  // Places an untouched page by the policy (home()'s first touch).
  int place_first(uint64_t page, int requester);
  // Makes `gpm` the home of an untouched page (every GPM's, replicated).
  // Homes come first in a GPM's DRAM: copies are dropped (any, the least
  // recently used first) when a new home needs their room; data that does
  // not fit without them is an Error naming the GPM and dram.capacity.
  void set_home(uint64_t page, int gpm);
  // Room left for copies on `gpm` (copy cap and DRAM), in bytes.
  uint64_t copy_room(int gpm) const;
  // Drops `gpm`'s copy used longest ago (LRU) or made first (FIFO), of an
  // earlier batch unless `any`; false when there is none.
  bool drop_copy(int gpm, bool any);
  // A page's data in whole lines: the unused end of a small buffer's page
  // holds nothing to copy.
  uint64_t page_data_bytes(uint64_t page) const;
  // The holder of the page fewest hops from `requester`: its home unless a
  // copy is nearer (the first such GPM in number order).
  int nearest_holder(uint64_t page, int requester) const {
    const int h = m_home[page];
    return (m_copies[page] & ~(1u << h)) ? nearest_copy(page, requester) : h;
  }
  int nearest_copy(uint64_t page, int requester) const;
  // Serves a line from GPM `src`'s L2 (DRAM on a miss).
  void serve(int src, uint64_t line, bool write, Category c, UnitTraffic& out);
  void move(int from, int to, uint64_t bytes, Category c, UnitTraffic& out);
  void writeback(int gpm, const Cache::Eviction& ev, UnitTraffic& out) {
    if (!ev.dirty) return;
    out.dram_write_bytes[size_t(gpm)] += m_line_bytes;
    m_totals.dram_write_bytes[size_t(gpm)][size_t(ev.category)] += m_line_bytes;
  }
  // access_lines()' lines moved between its GPM and another, counted per
  // direction, peer and category (m_tally) and moved in bulk at its end:
  // every count they reach is a sum of whole lines, the same in any order,
  // and a line's route is walked once per record, not once per line.
  void tally(size_t at) {
    if (m_tally[at]++ == 0) m_tallied.push_back(uint32_t(at));
  }
  void move_tallied(int gpm, UnitTraffic& out, uint64_t& hops);
  // Drops copies of `gpm` (not of the current batch) until `bytes` more fit;
  // false when they cannot.
  bool make_room(int gpm, uint64_t bytes);
  [[noreturn]] void out_of_dram(int gpm) const;
  // Sizes `out`'s per-GPM and per-link vectors for this machine when they are not.
  void shape(UnitTraffic& out) const;

  MemorySpec m_spec;
  const AddressMap& m_map;
  std::unique_ptr<PlacementPolicy> m_policy;
  std::unique_ptr<Topology> m_topology;
  std::vector<Cache> m_l1, m_l2, m_remote;
  std::vector<int8_t> m_home;      // per page
  std::vector<uint32_t> m_copies;  // per page: bit g set when GPM g holds a copy
  // Copies ahead of use: bytes per GPM, and per (page, GPM) when the copy
  // was made or (LRU) last read, in batches and units.
  std::vector<uint64_t> m_copy_bytes, m_copy_peak;
  std::vector<uint64_t> m_homed_bytes;  // per GPM: homes and replicas
  std::vector<uint32_t> m_made;         // per page: bit g set when g's copy was made by preallocate()
  std::vector<uint64_t> m_copy_stamp;
  uint64_t m_clock = 1, m_batch_start = 1;
  bool m_copy_lru = true;
  uint64_t m_page_bytes, m_line_bytes;
  int m_line_shift, m_page_shift;
  TrafficTotals m_totals;
  std::vector<uint32_t> m_hops;  // [from * gpms + to]: the route's links
  // access_lines()' lines to move: [(direction * gpms + peer) * kCategories
  // + category], direction 0 to the peer (writes through to their home), 1
  // from it (reads); the entries in use listed in m_tallied.
  std::vector<uint64_t> m_tally;
  std::vector<uint32_t> m_tallied;
};

}  // namespace oovr
