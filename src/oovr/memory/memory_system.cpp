#include "oovr/memory/memory_system.h"

#include <algorithm>
#include <bit>
#include <tuple>
#include <utility>

#include "oovr/core/error.h"
#include "oovr/core/host.h"

namespace oovr {

void UnitTraffic::reset(int gpms, int links) {
  // The vectors' storage is kept (a unit's traffic is reset for every
  // piece of work a replay adds: their allocations were 1% of one).
  std::vector<uint64_t> reads = std::move(dram_read_bytes), writes = std::move(dram_write_bytes),
                        on_links = std::move(link_bytes);
  *this = UnitTraffic{};
  reads.assign(size_t(gpms), 0);
  writes.assign(size_t(gpms), 0);
  on_links.assign(size_t(links), 0);
  dram_read_bytes = std::move(reads);
  dram_write_bytes = std::move(writes);
  link_bytes = std::move(on_links);
}

UnitTraffic& UnitTraffic::operator+=(const UnitTraffic& o) {
  accesses += o.accesses;
  l1_hits += o.l1_hits;
  l2_hits += o.l2_hits;
  remote_hits += o.remote_hits;
  home_l2_hits += o.home_l2_hits;
  dram_lines += o.dram_lines;
  l2_read_hits += o.l2_read_hits;
  local_dram_reads += o.local_dram_reads;
  remote_dram_reads += o.remote_dram_reads;
  remote_hops += o.remote_hops;
  for (size_t g = 0; g < o.dram_read_bytes.size(); ++g) {
    dram_read_bytes[g] += o.dram_read_bytes[g];
    dram_write_bytes[g] += o.dram_write_bytes[g];
  }
  for (size_t l = 0; l < o.link_bytes.size(); ++l) link_bytes[l] += o.link_bytes[l];
  for (size_t c = 0; c < inter_gpm_bytes.size(); ++c) inter_gpm_bytes[c] += o.inter_gpm_bytes[c];
  return *this;
}

uint64_t UnitTraffic::total_link_bytes() const {
  uint64_t s = 0;
  for (uint64_t b : link_bytes) s += b;
  return s;
}

uint64_t UnitTraffic::total_inter_gpm_bytes() const {
  uint64_t s = 0;
  for (uint64_t b : inter_gpm_bytes) s += b;
  return s;
}

uint64_t MemorySystem::state_bytes(const MemorySpec& spec, const AddressMap& map) {
  const uint64_t line = spec.line.value;
  const uint64_t gpms = uint64_t(spec.gpms), sms = uint64_t(spec.sms_per_gpm);
  const uint64_t caches = gpms * sms * Cache::state_bytes(spec.l1, line) +
                          gpms * (Cache::state_bytes(spec.l2, line) + Cache::state_bytes(spec.remote, line));
  const uint64_t per_page = sizeof(int8_t) + 2 * sizeof(uint32_t) + gpms * sizeof(uint64_t);
  return caches + map.pages() * per_page;
}

MemorySystem::MemorySystem(const MemorySpec& spec, const AddressMap& map)
    : m_spec(spec), m_map(map), m_page_bytes(map.page_bytes()), m_line_bytes(map.line_bytes()) {
  if (map.line_bytes() != spec.line.value || map.page_bytes() != spec.page.value)
    throw Error("memory system: the address map's page and line sizes differ from the memory spec's");
  if (spec.gpms > 32) throw Error("memory system: at most 32 GPMs");
  m_line_shift = __builtin_ctzll(m_line_bytes);
  m_page_shift = __builtin_ctzll(m_page_bytes);
  m_policy = PlacementPolicies::find(spec.placement)->make(spec.gpms);
  m_topology = Topologies::find(spec.topology)->make(spec.gpms);
  // Asked before the allocations: 32 GPMs of 1,024 SMs with 16 MB L1s would
  // be about 110 GB of tags, which a cgroup's limit answers with SIGKILL.
  check_memory_room(state_bytes(spec, map), "the memory system (" + std::to_string(spec.gpms) + " GPMs of " +
                                                std::to_string(spec.sms_per_gpm) + " SMs: its caches' tags and pages' state)");
  for (int g = 0; g < spec.gpms; ++g) {
    for (int s = 0; s < spec.sms_per_gpm; ++s)
      m_l1.emplace_back(spec.l1, m_line_bytes, "gpm[" + std::to_string(g) + "].sm[" + std::to_string(s) + "].l1");
    m_l2.emplace_back(spec.l2, m_line_bytes, "gpm[" + std::to_string(g) + "].l2");
    m_remote.emplace_back(spec.remote, m_line_bytes, "gpm[" + std::to_string(g) + "].remote");
  }
  // Caches keep 32-bit tags: every line of the map must have one.
  if (map.pages() > 0 && !m_l1.empty()) {
    const uint64_t last_line = (map.pages() * m_page_bytes - 1) >> m_line_shift;
    for (const Cache* c : {&m_l1.front(), &m_l2.front(), &m_remote.front()})
      if (!c->holds(last_line))
        throw Error("memory system: the address map (" + std::to_string(map.pages()) + " pages) is past what cache " + c->name() +
                    "'s tags can name");
  }
  m_home.assign(map.pages(), -1);
  m_copies.assign(map.pages(), 0);
  m_copy_bytes.assign(size_t(spec.gpms), 0);
  m_copy_peak.assign(size_t(spec.gpms), 0);
  m_homed_bytes.assign(size_t(spec.gpms), 0);
  m_made.assign(map.pages(), 0);
  m_copy_stamp.assign(map.pages() * size_t(spec.gpms), 0);
  m_copy_lru = spec.copy_eviction == "lru";
  const size_t links = m_topology->links().size();
  m_totals.link_bytes.assign(links, PerCategory{});
  m_totals.dram_read_bytes.assign(size_t(spec.gpms), PerCategory{});
  m_totals.dram_write_bytes.assign(size_t(spec.gpms), PerCategory{});
  m_totals.delivered.assign(size_t(spec.gpms) * size_t(spec.gpms), 0);
  m_totals.moved.assign(size_t(spec.gpms) * size_t(spec.gpms), 0);
  m_hops.resize(size_t(spec.gpms) * size_t(spec.gpms));
  for (int from = 0; from < spec.gpms; ++from)
    for (int to = 0; to < spec.gpms; ++to) m_hops[size_t(from * spec.gpms + to)] = uint32_t(m_topology->route(from, to).size());
  m_tally.assign(2 * size_t(spec.gpms) * kCategories, 0);
}

void MemorySystem::set_home(uint64_t page, int gpm) {
  m_home[page] = int8_t(gpm);
  m_copies[page] = m_policy->replicate_all() ? (m_spec.gpms == 32 ? ~0u : (1u << m_spec.gpms) - 1) : (1u << gpm);
  // The page's data now lives in the DRAM of every GPM holding it; copies
  // give way to it.
  const uint64_t bytes = page_data_bytes(page);
  const uint64_t capacity = m_spec.dram_capacity.value;
  for (uint32_t m = m_copies[page]; m; m &= m - 1) {
    const int g = __builtin_ctz(m);
    uint64_t& homed = m_homed_bytes[size_t(g)];
    homed += bytes;
    if (homed > capacity) out_of_dram(g);
    while (homed + m_copy_bytes[size_t(g)] > capacity)
      if (!drop_copy(g, true)) out_of_dram(g);
  }
}

void MemorySystem::out_of_dram(int gpm) const {
  throw Error("GPM " + std::to_string(gpm) + "'s DRAM (dram.capacity = " + format_bytes(m_spec.dram_capacity) +
              ") cannot hold the data placed there: " + format_bytes(Bytes{m_homed_bytes[size_t(gpm)]}) +
              " of buffers, textures and framebuffers");
}

uint64_t MemorySystem::copy_room(int gpm) const {
  const uint64_t capacity = m_spec.dram_capacity.value, homed = m_homed_bytes[size_t(gpm)];
  uint64_t room = homed < capacity ? capacity - homed : 0;
  if (m_spec.copy_capacity.value) room = std::min(room, m_spec.copy_capacity.value);
  return room;
}

uint64_t MemorySystem::page_data_bytes(uint64_t page) const {
  return (m_map.page_used_bytes(page) + m_line_bytes - 1) / m_line_bytes * m_line_bytes;
}

int MemorySystem::place_first(uint64_t page, int requester) {
  const int h = m_policy->assign(page, m_map.region_of_page(page), requester);
  set_home(page, h);
  return h;
}

int MemorySystem::nearest_copy(uint64_t page, int requester) const {
  int best = m_home[page];
  uint32_t hops = m_hops[size_t(best * m_spec.gpms + requester)];
  for (uint32_t m = m_copies[page]; m; m &= m - 1) {
    const int g = __builtin_ctz(m);
    const uint32_t h = m_hops[size_t(g * m_spec.gpms + requester)];
    if (h < hops) {
      best = g;
      hops = h;
    }
  }
  return best;
}

void MemorySystem::shape(UnitTraffic& out) const {
  if (out.link_bytes.size() != m_topology->links().size() || out.dram_read_bytes.size() != size_t(m_spec.gpms))
    out.reset(m_spec.gpms, int(m_topology->links().size()));
}

void MemorySystem::serve(int src, uint64_t line, bool write, Category c, UnitTraffic& out) {
  Cache::Eviction ev;
  if (m_l2[size_t(src)].access(line, write, c, ev)) {
    writeback(src, ev, out);
    return;
  }
  writeback(src, ev, out);
  if (!write) {
    ++out.dram_lines;
    out.dram_read_bytes[size_t(src)] += m_line_bytes;
    m_totals.dram_read_bytes[size_t(src)][size_t(c)] += m_line_bytes;
  }
}

void MemorySystem::move(int from, int to, uint64_t bytes, Category c, UnitTraffic& out) {
  for (int l : m_topology->route(from, to)) {
    out.link_bytes[size_t(l)] += bytes;
    m_totals.link_bytes[size_t(l)][size_t(c)] += bytes;
  }
  out.inter_gpm_bytes[size_t(c)] += bytes;
  m_totals.inter_gpm_bytes[size_t(c)] += bytes;
  m_totals.moved[size_t(from * m_spec.gpms + to)] += bytes;
}

void MemorySystem::access(int gpm, int sm, std::span<const LineAccess> lines, UnitTraffic& out, uint64_t l1_repeats) {
  access_lines(gpm, sm, nullptr, {}, lines, TileLines{}, out, l1_repeats);
}

void MemorySystem::access(int gpm, int sm, const SceneLayout& layout, std::span<const TexLine> texture_reads,
                          const TileLines& tile, UnitTraffic& out, uint64_t l1_repeats) {
  access_lines(gpm, sm, &layout, texture_reads, {}, tile, out, l1_repeats);
}

void MemorySystem::access(int gpm, int sm, const SceneLayout& layout, std::span<const TexLine> texture_reads,
                          std::span<const LineAccess> lines, UnitTraffic& out, uint64_t l1_repeats) {
  access_lines(gpm, sm, &layout, texture_reads, lines, TileLines{}, out, l1_repeats);
}

void MemorySystem::access_lines(int gpm, int sm, const SceneLayout* layout, std::span<const TexLine> texture_reads,
                                std::span<const LineAccess> lines, const TileLines& tile, UnitTraffic& out, uint64_t l1_repeats) {
  if (gpm < 0 || gpm >= m_spec.gpms || sm < 0 || sm >= m_spec.sms_per_gpm)
    throw Error("memory access by GPM " + std::to_string(gpm) + " SM " + std::to_string(sm) + ", which does not exist");
  shape(out);
  Cache& l1 = m_l1[size_t(gpm * m_spec.sms_per_gpm + sm)];
  Cache& l2 = m_l2[size_t(gpm)];
  Cache& rc = m_remote[size_t(gpm)];
  const uint32_t me = 1u << gpm;
  // The page tables cover the address map as it was when this memory system
  // was built; regions added later are not addressable.
  const uint64_t end = m_home.size() * m_page_bytes;
  // Hit counters stay in registers; the hot path (an L1 hit) touches only
  // the L1's own arrays.
  uint64_t l1_hits = l1_repeats, l2_hits = 0, l2_read_hits = 0, remote_hits = 0, home_l2_hits = 0, local_dram = 0,
           local_delivered = 0, remote_dram = 0, hops = 0, l1_lookups = l1_repeats, l2_lookups = 0, remote_lookups = 0;
  const uint64_t dram_before = out.dram_lines;
  const uint64_t now = ++m_clock;
  // What an access that threw part-way tallied is dropped with it.
  for (const uint32_t at : m_tallied) m_tally[at] = 0;
  m_tallied.clear();
  // One line's access, each level's counters kept above.
  const auto one = [&](const LineAccess& a) __attribute__((always_inline)) {
    if (a.address >= end) [[unlikely]]
      throw Error("memory access at address " + std::to_string(a.address) + ", past the address map");
    const uint64_t line = a.address >> m_line_shift;
    Cache::Eviction ev;
    if (uses_l1(a.category) && !a.write) {
      // An L1 hit means the page was touched before: its home is known.
      ++l1_lookups;
      if (l1.access(line, false, a.category, ev)) {
        ++l1_hits;
        return;
      }
    }
    const uint64_t page = a.address >> m_page_shift;
    const int h = home(page, gpm);
    if (h == gpm || (m_copies[page] & me)) {
      // Local: this GPM's L2, then its DRAM.
      if (m_copy_lru && h != gpm) m_copy_stamp[page * uint64_t(m_spec.gpms) + uint64_t(gpm)] = now;
      ++l2_lookups;
      if (l2.access(line, a.write, a.category, ev)) {
        ++l2_hits;
        l2_read_hits += !a.write;
      } else if (!a.write) {
        ++local_dram;
        out.dram_read_bytes[size_t(gpm)] += m_line_bytes;
        m_totals.dram_read_bytes[size_t(gpm)][size_t(a.category)] += m_line_bytes;
      }
      writeback(gpm, ev, out);
      if (!a.write) local_delivered += m_line_bytes;
      return;
    }
    if (a.write) {
      // Write-through to the home over the links; a cached copy is dropped.
      rc.invalidate(line);
      tally(size_t(h) * kCategories + size_t(a.category));
      ++l2_lookups;
      serve(h, line, true, a.category, out);
      return;
    }
    ++remote_lookups;
    if (rc.access(line, false, a.category, ev)) {
      ++remote_hits;
      return;
    }
    const int src = nearest_holder(page, gpm);
    const uint64_t before = out.dram_lines;
    ++l2_lookups;
    serve(src, line, false, a.category, out);
    if (out.dram_lines == before) ++home_l2_hits;
    else ++remote_dram;
    tally((size_t(m_spec.gpms) + size_t(src)) * kCategories + size_t(a.category));
  };
  // A record's texture reads (FrameSim::replay) come as the trace lists
  // them: their addresses are found here rather than copied into `lines`.
  if (layout)
    for (const TexLine t : texture_reads) one(LineAccess{layout->texture_line(t), Category::texture, false});
  for (const LineAccess& a : lines) one(a);
  // The framebuffer's lines, line by line (only the lines a mask names),
  // counted as they go (std::popcount is a library call without -mpopcnt);
  // the four kinds written out (a loop over a table of them took 1.1 billion
  // more instructions of the 24-point slice: performance.md).
  uint64_t tile_lines = 0;
  for (uint32_t m = tile.depth_read | tile.colour_read | tile.depth_write | tile.colour_write; m; m &= m - 1) {
    const int l = std::countr_zero(m);
    const uint32_t bit = 1u << l;
    const uint64_t at = uint64_t(l) << m_line_shift;
    if (tile.depth_read & bit) {
      one(LineAccess{tile.depth + at, Category::depth, false});
      ++tile_lines;
    }
    if (tile.colour_read & bit) {
      one(LineAccess{tile.colour + at, Category::colour, false});
      ++tile_lines;
    }
    if (tile.depth_write & bit) {
      one(LineAccess{tile.depth + at, Category::depth, true});
      ++tile_lines;
    }
    if (tile.colour_write & bit) {
      one(LineAccess{tile.colour + at, Category::colour, true});
      ++tile_lines;
    }
  }
  move_tallied(gpm, out, hops);
  out.dram_lines += local_dram;
  out.accesses += texture_reads.size() + lines.size() + tile_lines + l1_repeats;
  out.l1_hits += l1_hits;
  out.l2_hits += l2_hits;
  out.remote_hits += remote_hits;
  out.home_l2_hits += home_l2_hits;
  out.l2_read_hits += l2_read_hits;
  out.local_dram_reads += local_dram;
  out.remote_dram_reads += remote_dram;
  out.remote_hops += hops;
  m_totals.delivered[size_t(gpm * m_spec.gpms + gpm)] += local_delivered;
  m_totals.dram_lines += out.dram_lines - dram_before;
  m_totals.accesses += texture_reads.size() + lines.size() + tile_lines + l1_repeats;
  m_totals.l1_hits += l1_hits;
  m_totals.l2_hits += l2_hits;
  m_totals.remote_hits += remote_hits;
  m_totals.home_l2_hits += home_l2_hits;
  m_totals.l1_lookups += l1_lookups;
  m_totals.l2_lookups += l2_lookups;
  m_totals.remote_lookups += remote_lookups;
}

void MemorySystem::move_tallied(int gpm, UnitTraffic& out, uint64_t& hops) {
  const size_t n = size_t(m_spec.gpms);
  for (const uint32_t at : m_tallied) {
    const uint64_t lines = std::exchange(m_tally[at], 0);
    const auto c = Category(at % kCategories);
    const size_t peer = (at / kCategories) % n;
    const bool in = at / kCategories >= n;
    const int from = in ? int(peer) : gpm, to = in ? gpm : int(peer);
    move(from, to, lines * m_line_bytes, c, out);
    if (in) {
      // Reads served by another GPM: their hops and the bytes it delivered.
      hops += lines * m_hops[peer * n + size_t(gpm)];
      m_totals.delivered[peer * n + size_t(gpm)] += lines * m_line_bytes;
    }
  }
  m_tallied.clear();
}

bool MemorySystem::drop_copy(int gpm, bool any) {
  // The copy used longest ago (LRU) or made first (FIFO), not one of the
  // current batch unless `any`; ties to the lowest page.
  const uint64_t n = uint64_t(m_spec.gpms);
  const uint64_t limit = any ? ~uint64_t(0) : m_batch_start;
  uint64_t victim = ~uint64_t(0), oldest = ~uint64_t(0);
  for (uint64_t p = 0; p < m_home.size(); ++p) {
    if (!(m_made[p] & (1u << gpm))) continue;
    const uint64_t stamp = m_copy_stamp[p * n + uint64_t(gpm)];
    if (stamp < limit && stamp < oldest) {
      oldest = stamp;
      victim = p;
    }
  }
  if (victim == ~uint64_t(0)) return false;
  m_copies[victim] &= ~(1u << gpm);
  m_made[victim] &= ~(1u << gpm);
  m_copy_bytes[size_t(gpm)] -= page_data_bytes(victim);
  ++m_totals.copies_evicted;
  return true;
}

bool MemorySystem::make_room(int gpm, uint64_t bytes) {
  const uint64_t room = copy_room(gpm);
  if (bytes > room) return false;  // not even with every other copy gone
  while (m_copy_bytes[size_t(gpm)] + bytes > room)
    if (!drop_copy(gpm, false)) return false;
  return true;
}

uint64_t MemorySystem::preallocate(uint64_t address, uint64_t bytes, int gpm, UnitTraffic& out) {
  if (gpm < 0 || gpm >= m_spec.gpms) throw Error("pre-allocation to GPM " + std::to_string(gpm) + ", which does not exist");
  if (bytes == 0) return 0;
  if (address + bytes > m_home.size() * m_page_bytes) throw Error("pre-allocation past the end of the address map");
  shape(out);
  uint64_t copied = 0;
  const uint64_t n = uint64_t(m_spec.gpms);
  for (uint64_t page = address >> m_page_shift; page <= (address + bytes - 1) >> m_page_shift; ++page) {
    if (m_home[page] < 0) {
      // Untouched data is placed where it is needed: nothing to copy.
      set_home(page, gpm);
      continue;
    }
    if (m_copies[page] & (1u << gpm)) {
      // Already there; a copy is now in use by this batch.
      if (m_home[page] != gpm) m_copy_stamp[page * n + uint64_t(gpm)] = m_clock;
      continue;
    }
    const uint64_t bytes_here = page_data_bytes(page);
    if (!make_room(gpm, bytes_here)) {
      ++m_totals.copies_refused;
      continue;
    }
    const int src = nearest_holder(page, gpm);
    out.dram_read_bytes[size_t(src)] += bytes_here;
    m_totals.dram_read_bytes[size_t(src)][size_t(Category::prealloc)] += bytes_here;
    move(src, gpm, bytes_here, Category::prealloc, out);
    out.dram_write_bytes[size_t(gpm)] += bytes_here;
    m_totals.dram_write_bytes[size_t(gpm)][size_t(Category::prealloc)] += bytes_here;
    m_copies[page] |= 1u << gpm;
    m_made[page] |= 1u << gpm;
    m_copy_bytes[size_t(gpm)] += bytes_here;
    m_copy_peak[size_t(gpm)] = std::max(m_copy_peak[size_t(gpm)], m_copy_bytes[size_t(gpm)]);
    m_copy_stamp[page * n + uint64_t(gpm)] = m_clock;
    copied += bytes_here;
  }
  return copied;
}

void MemorySystem::transfer(int from, int to, uint64_t bytes, Category category, UnitTraffic& out) {
  if (from < 0 || from >= m_spec.gpms || to < 0 || to >= m_spec.gpms)
    throw Error("transfer between GPMs " + std::to_string(from) + " and " + std::to_string(to) + ", which do not both exist");
  shape(out);
  if (from != to) move(from, to, bytes, category, out);
}

void MemorySystem::pin(uint32_t region, int gpm) { m_policy->pin(region, gpm); }

bool MemorySystem::place(uint64_t address, int gpm) {
  if (gpm < 0 || gpm >= m_spec.gpms) throw Error("placement on GPM " + std::to_string(gpm) + ", which does not exist");
  const uint64_t page = address >> m_page_shift;
  if (page >= m_home.size()) throw Error("placement past the end of the address map");
  if (m_home[page] >= 0) return false;
  set_home(page, gpm);
  return true;
}

void MemorySystem::end_draw(int gpm) {
  if (m_spec.remote_invalidate != "draw") return;
  if (gpm < 0) {
    for (Cache& c : m_remote) c.invalidate_all();
  } else {
    if (gpm >= m_spec.gpms) throw Error("end of a draw on GPM " + std::to_string(gpm) + ", which does not exist");
    m_remote[size_t(gpm)].invalidate_all();
  }
}

void MemorySystem::end_frame() {
  if (m_spec.remote_invalidate == "draw" || m_spec.remote_invalidate == "frame")
    for (Cache& c : m_remote) c.invalidate_all();
}

bool MemorySystem::holds(int gpm, uint64_t address) const {
  const uint64_t page = address >> m_page_shift;
  return page < m_home.size() && m_home[page] >= 0 && (m_copies[page] & (1u << gpm));
}

std::vector<uint64_t> MemorySystem::resident_bytes() const {
  std::vector<uint64_t> r(size_t(m_spec.gpms), 0);
  for (size_t p = 0; p < m_home.size(); ++p) {
    if (m_home[p] < 0) continue;
    // Data bytes, not whole pages: a small buffer alone in its page counts
    // its own size, as a driver packing small buffers would allocate.
    const uint64_t used = m_map.page_used_bytes(p);
    for (uint32_t m = m_copies[p]; m; m &= m - 1) r[size_t(__builtin_ctz(m))] += used;
  }
  return r;
}

uint64_t MemorySystem::footprint_bytes() const {
  uint64_t s = 0;
  for (uint64_t b : resident_bytes()) s += b;
  return s;
}

void MemorySystem::report(Stats& out) const {
  const TrafficTotals& t = m_totals;
  out.count("memory", "accesses", t.accesses);
  out.count("l1", "served", t.l1_hits);
  out.count("l2", "served", t.l2_hits);
  out.count("remote_cache", "served", t.remote_hits);
  out.count("home_l2", "served", t.home_l2_hits);
  out.count("dram", "served", t.dram_lines);
  // Energy (docs/model.md, "Energy"): what each lookup, and each bit a
  // DRAM or link moves, costs; metrics_of integrates them over the counts
  // (run/result_metrics.h, energy_of), so the counts stay exact.
  const double line_bits = double(m_line_bytes) * 8;
  for (const auto& [location, lookups, spec] :
       {std::tuple{"l1", t.l1_lookups, &m_spec.l1}, std::tuple{"l2", t.l2_lookups, &m_spec.l2},
        std::tuple{"remote_cache", t.remote_lookups, &m_spec.remote}}) {
    out.count(location, "lookups", lookups);
    out.add(location, "energy_per_lookup", spec->energy_per_bit.value * line_bits, "J", Merge::max);
  }
  const auto gpm = [](int g) { return "gpm[" + std::to_string(g) + "]"; };
  const auto sum = [](const PerCategory& c) {
    uint64_t s = 0;
    for (uint64_t b : c) s += b;
    return s;
  };
  for (int g = 0; g < m_spec.gpms; ++g) {
    out.count(gpm(g) + ".dram", "bytes", sum(t.dram_read_bytes[size_t(g)]) + sum(t.dram_write_bytes[size_t(g)]), "B");
    out.add(gpm(g) + ".dram", "energy_per_bit", m_spec.dram_energy_per_bit.value, "J/bit", Merge::max);
  }
  for (size_t l = 0; l < t.link_bytes.size(); ++l) {
    out.count(m_topology->link_location(int(l)), "bytes", sum(t.link_bytes[l]), "B");
    out.add(m_topology->link_location(int(l)), "energy_per_bit", m_spec.link_energy_per_bit.value, "J/bit", Merge::max);
  }
  const size_t n = size_t(m_spec.gpms);
  for (size_t from = 0; from < n; ++from)
    for (size_t to = 0; to < n; ++to)
      if (from != to) out.count(gpm(int(from)) + "->" + gpm(int(to)), "bytes", t.moved[from * n + to], "B");
  out.count("memory", "copies_evicted", t.copies_evicted);
  out.count("memory", "copies_refused", t.copies_refused);
}

}  // namespace oovr
