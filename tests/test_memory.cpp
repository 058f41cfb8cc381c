// The memory system, with exact expectations (given / when / then).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "oovr/core/error.h"
#include "oovr/core/rng.h"
#include "oovr/memory/memory_system.h"
#include "oovr/memory/replacement/i_replacement.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/run/result_metrics.h"
#include "oovr/scene/builtin.h"
#include "oovr/timing/gpm_model.h"
#include "test_util.h"
#include "texture_records.h"
#include "traffic_totals.h"

namespace oovr {
namespace {

constexpr uint64_t kLine = 128, kPage = 64 << 10;

MemorySpec spec_with(std::initializer_list<const char*> settings) {
  Config c;
  for (const char* s : settings) c.set(s);
  const MemorySpec spec = MemorySpec::from_config(c);
  c.check_all_used();
  return spec;
}

std::vector<LineAccess> reads(uint64_t base, uint64_t bytes, Category c = Category::texture) {
  std::vector<LineAccess> v;
  for (uint64_t a = base; a < base + bytes; a += kLine) v.push_back({a, c, false});
  return v;
}

int link_id(const Topology& t, int from, int to) {
  for (size_t l = 0; l < t.links().size(); ++l)
    if (t.links()[l].from == from && t.links()[l].to == to) return int(l);
  return -1;
}

struct Fixture {
  MemorySpec spec;
  AddressMap map;
  std::unique_ptr<MemorySystem> mem;
  UnitTraffic u;
  explicit Fixture(const MemorySpec& s) : spec(s), map(s.page, s.line) {}
  void build() { mem = std::make_unique<MemorySystem>(spec, map); }
  UnitTraffic& run(int gpm, int sm, const std::vector<LineAccess>& a) {
    u.reset(spec.gpms, int(mem->topology().links().size()));
    mem->access(gpm, sm, a, u);
    return u;
  }
};

// ARecordsRepeatsLeftOutChangeNoHitNorWhatTheCacheHolds with a cache of
// `ways` ways.
void records_without_repeats_hit_and_hold_the_same(int ways) {
  constexpr int kSets = 4;
  FrameTrace trace;
  Rng rng(11);
  test::add_random_records(trace, rng, {.records = 3000, .sets = kSets, .fewest = 1, .spread = 48});
  // The cache's line of a texture line: each texture's base a multiple of
  // the sets, so a line's set is its index's.
  const auto line_of = [](TexLine l) { return uint64_t(tex_line_texture(l)) * 1024 + tex_line_index(l); };
  const auto simple = trace.tex_lines_without_repeats(kSets);
  const auto with_lru = trace.tex_lines_without_repeats(kSets, ways);
  ASSERT_NE(simple, nullptr);
  ASSERT_NE(with_lru, nullptr);
  // Each rule leaves lines out, the LRU rule more (30,990 of 74,100 stay by
  // the first; by both 29,646, 27,368 and 26,666 with 2, 4 and 8 ways).
  EXPECT_LT(simple->lines.size(), trace.tex_lines.size() * 3 / 4);
  EXPECT_LT(with_lru->lines.size(), simple->lines.size() * 97 / 100);
  for (const char* policy : {"lru", "fifo", "random"}) {
    const auto& kept = std::string(policy) == "lru" ? with_lru : simple;
    CacheSpec spec;
    spec.size = Bytes{uint64_t(kSets * ways) * kLine};
    spec.ways = ways;
    spec.replacement = policy;
    Cache whole(spec, kLine, "test"), filtered(spec, kLine, "test");
    uint64_t misses = 0;
    for (size_t r = 0; r < trace.tiles.size(); ++r) {
      const TileWork& t = trace.tiles[r];
      Cache::Eviction ev;
      // The lines that missed, in order: the same misses, one by one.
      std::vector<uint64_t> miss_whole, miss_filtered;
      for (uint64_t i = t.tex_begin; i < t.tex_begin + t.tex_count; ++i)
        if (!whole.access(line_of(trace.tex_lines[i]), false, Category::texture, ev))
          miss_whole.push_back(line_of(trace.tex_lines[i]));
      for (uint64_t i = kept->begin[r]; i < kept->begin[r + 1]; ++i)
        if (!filtered.access(line_of(kept->lines[i]), false, Category::texture, ev))
          miss_filtered.push_back(line_of(kept->lines[i]));
      ASSERT_EQ(miss_whole, miss_filtered) << policy << ", record " << r;
      for (uint64_t tex = 0; tex < 2; ++tex)
        for (uint64_t index = 0; index < 40; ++index)
          ASSERT_EQ(whole.contains(tex * 1024 + index), filtered.contains(tex * 1024 + index))
              << policy << ", record " << r << ", line " << tex << ":" << index;
      misses += miss_whole.size();
    }
    EXPECT_GT(misses, 5000u) << policy << ": the records must miss, or the order of the sets would not be tested";
  }
}

TEST(Cache, ARecordsRepeatsLeftOutChangeNoHitNorWhatTheCacheHolds) {
  // FrameSim::replay leaves a record's repeats out of its L1 reads
  // (FrameTrace::tex_lines_without_repeats): the re-reads of a set's last
  // line with any policy, and with LRU the sure hits read again before the
  // set may miss. A cache of 4 sets fed 3,000 random records
  // whole, and one fed them without their repeats: after every record the
  // same misses and the same lines held, with every policy. The records
  // re-read the line just read (50%), cycle among 2 to 6 lines of one set
  // (40%: the alternating layers the LRU rule is for) and draw from 80.
  // Four ways (Table 1's L1), two and eight. That the filter leaves out all
  // it may is Trace.TextureLinesWithoutRepeatsAreWhatTheRulesSay's.
  for (const int ways : {4, 2, 8}) {
    SCOPED_TRACE(std::to_string(ways) + " ways");
    records_without_repeats_hit_and_hold_the_same(ways);
  }
}

// A small cache (4 sets of `ways` ways) against a reference kept as lists
// in order of use (LRU) or of insertion (FIFO), on a stream that re-reads
// the line just read half the time (the lookup Cache::access skips), writes
// now and then in one of three categories, and invalidates a line, or
// everything, now and then: the same hits, misses, dirty evictions (line and
// category), dirty lines dropped and lines held, access by access. LRU's
// sets are kept in order of use, FIFO's with counters (Cache). With `wrap`,
// the cache's 32-bit access counter is moved to within a few hundred
// accesses of its end every 2,000 accesses, so that it is renumbered ten
// times in the stream, between accesses to every set (counters only).
void expect_reference_answers(bool wrap, int ways) {
  for (const char* policy : {"lru", "fifo"}) {
    CacheSpec spec;
    spec.size = Bytes{uint64_t(4 * ways) * kLine};
    spec.ways = ways;
    spec.replacement = policy;
    Cache cache(spec, kLine, "test");
    struct Held {
      uint64_t line;
      bool dirty;
      Category category;
    };
    std::vector<std::vector<Held>> sets(4);  // per set, oldest first
    const bool lru = std::string(policy) == "lru";
    const Category categories[] = {Category::texture, Category::depth, Category::colour};
    const uint64_t lines = uint64_t(10 * ways);
    Rng rng(7);
    uint64_t previous = 0, hits = 0, evictions = 0, dropped = 0;
    const std::string at = std::string(policy) + ", " + std::to_string(ways) + " ways, access ";
    for (int k = 0; k < 20000; ++k) {
      if (wrap && k % 2000 == 0) cache.skip_clock_to(100 + rng.below(400));
      const uint64_t line = rng.below(2) ? previous : rng.below(lines);
      const bool write = rng.below(8) == 0;
      const Category category = categories[rng.below(3)];
      auto& set = sets[line % 4];
      if (rng.below(50) == 0) {
        cache.invalidate(line);
        std::erase_if(set, [&](const Held& e) { return e.line == line; });
        continue;
      }
      if (rng.below(2000) == 0) {
        uint64_t dirty = 0;
        for (auto& held : sets) {
          for (const Held& e : held) dirty += e.dirty;
          held.clear();
        }
        ASSERT_EQ(cache.invalidate_all(), dirty) << at << k;
        dropped += dirty;
        continue;
      }
      Cache::Eviction ev;
      const bool hit = cache.access(line, write, category, ev);
      const auto it = std::find_if(set.begin(), set.end(), [&](const Held& e) { return e.line == line; });
      ASSERT_EQ(hit, it != set.end()) << at << k;
      std::optional<Held> out;
      if (hit) {
        ++hits;
        it->dirty = it->dirty || write;
        if (lru) std::rotate(it, it + 1, set.end());
      } else {
        if (set.size() == size_t(ways)) {
          out = set.front();
          set.erase(set.begin());
          ++evictions;
        }
        set.push_back({line, write, category});
      }
      const bool dirty_out = out && out->dirty;
      ASSERT_EQ(ev.dirty, dirty_out) << at << k;
      if (dirty_out) {
        ASSERT_EQ(ev.line, out->line) << at << k;
        ASSERT_EQ(ev.category, out->category) << at << k;
      }
      const uint64_t other = rng.below(lines);
      const auto& other_set = sets[other % 4];
      ASSERT_EQ(cache.contains(other),
                std::any_of(other_set.begin(), other_set.end(), [&](const Held& e) { return e.line == other; }))
          << at << k << ", line " << other;
      previous = line;
    }
    // The stream exercised every path: hits, re-reads, evictions, and
    // (where the lines are few enough to stay) dirty lines dropped at once.
    EXPECT_GT(hits, 8000u) << policy << ", " << ways << " ways";
    EXPECT_GT(evictions, 1000u) << policy << ", " << ways << " ways";
    EXPECT_GT(dropped, 0u) << policy << ", " << ways << " ways";
  }
}

TEST(Cache, EveryAccessAnswersAsAReferenceLruAndFifoWould) {
  for (int ways : {1, 2, 3, 4, 5, 8, 12, 16, 32, 64}) expect_reference_answers(false, ways);
}

TEST(Cache, ItsCountersRenumberedWhereTheyWouldWrapKeepEveryAnswer) { expect_reference_answers(true, 4); }

TEST(Cache, LruEvictsTheFirstWayOfTheOldestUseWhateverTheSetsWays) {
  // The policy's victim, for any number of ways: the first way of the
  // oldest use, ties (the first) and counters past 2^31 (unsigned) included.
  const std::unique_ptr<ReplacementPolicy> lru = ReplacementPolicies::find("lru")->make(0);
  Rng rng(5);
  int tied = 0, high = 0;
  for (int ways : {1, 2, 3, 4, 5, 8, 12, 16, 20, 32, 64}) {
    for (int trial = 0; trial < 3000; ++trial) {
      std::vector<uint32_t> use(static_cast<size_t>(ways)), inserted(static_cast<size_t>(ways), 0);
      // Few distinct values (ties), values on both sides of 2^31, or any.
      const int kind = trial % 3;
      for (auto& u : use)
        u = kind == 0   ? uint32_t(rng.uniform() * 4)
            : kind == 1 ? (rng.uniform() < 0.5 ? 0x7ffffffeu : 0x80000000u) + uint32_t(rng.uniform() * 3)
                        : uint32_t(rng.next());
      const auto oldest = std::min_element(use.begin(), use.end());
      const int expected = int(oldest - use.begin());
      tied += std::count(use.begin(), use.end(), *oldest) > 1;
      high += *oldest >= 0x80000000u;
      ASSERT_EQ(lru->victim({use.data(), inserted.data(), ways}), expected) << ways << " ways, trial " << trial;
    }
  }
  EXPECT_GT(tied, 3000);
  EXPECT_GT(high, 1000);
}

TEST(Cache, ALinePastWhatItsTagsNameIsRefusedAndHitsNothing) {
  // 4 sets: a tag is the line number less its 2 set bits, in 32 bits. Line
  // 5 and line 5 + 2^34 have tags 1 and 2^32 + 1, the same low 32 bits.
  CacheSpec spec;
  spec.size = Bytes{16 * kLine};
  spec.ways = 4;
  Cache cache(spec, kLine, "test");
  const uint64_t near = 5, far = near + (uint64_t(1) << 34);
  EXPECT_TRUE(cache.holds(near));
  EXPECT_FALSE(cache.holds(far));
  Cache::Eviction ev;
  EXPECT_FALSE(cache.access(near, false, Category::texture, ev));
  EXPECT_TRUE(cache.access(near, true, Category::texture, ev)) << "a write looks the tags up";
  EXPECT_FALSE(cache.contains(far));
  EXPECT_THROW(cache.access(far, true, Category::texture, ev), Error);
  EXPECT_TRUE(cache.contains(near));
}

TEST(Memory, ColdRemoteReadCrossesItsLinkExactlyOnce) {
  // Given a 64 KB texture pinned to GPM 1 and cold caches,
  Fixture f(spec_with({"memory.placement=pinned"}));
  const uint32_t tex = f.map.add("texture", Category::texture, 64 << 10);
  f.build();
  f.mem->pin(tex, 1);
  // when GPM 0 reads all of it,
  const UnitTraffic& u = f.run(0, 0, reads(f.map.region(tex).base, 64 << 10));
  // then exactly 64 KB cross link 1->0, nothing else moves, nothing hits.
  const int l10 = link_id(f.mem->topology(), 1, 0);
  for (size_t l = 0; l < u.link_bytes.size(); ++l) EXPECT_EQ(u.link_bytes[l], int(l) == l10 ? 64u << 10 : 0u) << l;
  EXPECT_EQ(u.l1_hits + u.l2_hits + u.remote_hits + u.home_l2_hits, 0u);
  EXPECT_EQ(u.dram_lines, 512u);
  EXPECT_EQ(u.dram_read_bytes[1], 64u << 10);
  EXPECT_EQ(u.dram_read_bytes[0], 0u);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::texture)], 64u << 10);
  EXPECT_EQ(f.mem->totals().link_bytes[size_t(l10)][size_t(Category::texture)], 64u << 10);
}

TEST(Memory, RereadsHitL1ThenTheRemoteCacheThenTheHomeL2) {
  Fixture f(spec_with({"memory.placement=pinned"}));
  const uint32_t tex = f.map.add("texture", Category::texture, 64 << 10);
  f.build();
  f.mem->pin(tex, 1);
  const auto all = reads(f.map.region(tex).base, 64 << 10);
  f.run(0, 0, all);
  // The same SM again: its L1 (128 KB) holds all 512 lines.
  EXPECT_EQ(f.run(0, 0, all).l1_hits, 512u);
  // Another SM of GPM 0: its L1 is cold; the remote cache has every line.
  const UnitTraffic& second = f.run(0, 1, all);
  EXPECT_EQ(second.remote_hits, 512u);
  EXPECT_EQ(second.total_link_bytes(), 0u);
  // After the frame boundary the remote cache is empty; the lines cross the
  // link again, now from the home's L2 instead of its DRAM.
  f.mem->end_frame();
  const UnitTraffic& third = f.run(0, 2, all);
  EXPECT_EQ(third.remote_hits, 0u);
  EXPECT_EQ(third.home_l2_hits, 512u);
  EXPECT_EQ(third.dram_lines, 0u);
  EXPECT_EQ(third.total_link_bytes(), 64u << 10);
}

TEST(Memory, RemoteCacheInvalidationBoundaryIsConfigurable) {
  for (const char* boundary : {"draw", "frame", "never"}) {
    Fixture f(spec_with({"memory.placement=pinned", (std::string("cache.remote.invalidate=") + boundary).c_str()}));
    const uint32_t tex = f.map.add("texture", Category::texture, 8 << 10);
    f.build();
    f.mem->pin(tex, 1);
    const auto all = reads(f.map.region(tex).base, 8 << 10);
    f.run(0, 0, all);
    f.mem->end_draw();
    EXPECT_EQ(f.run(0, 1, all).remote_hits, std::string(boundary) == "draw" ? 0u : 64u) << boundary;
    f.mem->end_frame();
    EXPECT_EQ(f.run(0, 2, all).remote_hits, std::string(boundary) == "never" ? 64u : 0u) << boundary;
  }
}

TEST(Memory, FirstTouchGivesPagesToTheFirstToucher) {
  Fixture f(spec_with({}));
  const uint32_t buf = f.map.add("buffer", Category::texture, 4 * kPage);
  f.build();
  const uint64_t base = f.map.region(buf).base;
  f.run(2, 0, {{base, Category::texture, false}});
  f.run(3, 0, {{base + kPage, Category::texture, false}});
  EXPECT_EQ(f.mem->home_of(base), 2);
  EXPECT_EQ(f.mem->home_of(base + kPage + 5), 3);
  EXPECT_EQ(f.mem->home_of(base + 2 * kPage), -1) << "untouched";
  // GPM 3 reading GPM 2's page pulls it over link 2->3.
  const UnitTraffic& u = f.run(3, 0, {{base + kLine, Category::texture, false}});
  EXPECT_EQ(u.link_bytes[size_t(link_id(f.mem->topology(), 2, 3))], kLine);
}

TEST(Memory, InterleavedPagesRoundRobin) {
  Fixture f(spec_with({"memory.placement=interleaved"}));
  const uint32_t buf = f.map.add("buffer", Category::texture, 8 * kPage);
  f.build();
  const uint64_t base = f.map.region(buf).base;
  std::vector<LineAccess> a;
  for (int p = 0; p < 8; ++p) a.push_back({base + uint64_t(p) * kPage, Category::texture, false});
  f.run(0, 0, a);
  for (int p = 0; p < 8; ++p) EXPECT_EQ(f.mem->home_of(base + uint64_t(p) * kPage), p % 4);
}

TEST(Memory, ReplicationMakesEveryReadLocalAndMultipliesTheFootprint) {
  Fixture f(spec_with({"memory.placement=replicated"}));
  const uint32_t buf = f.map.add("buffer", Category::texture, 4 * kPage);
  f.build();
  for (int g = 0; g < 4; ++g) {
    const UnitTraffic& u = f.run(g, 0, reads(f.map.region(buf).base, 4 * kPage));
    EXPECT_EQ(u.total_link_bytes(), 0u);
    EXPECT_EQ(u.dram_read_bytes[size_t(g)], 4 * kPage);
  }
  EXPECT_EQ(f.mem->footprint_bytes(), 4 * 4 * kPage);
}

TEST(Memory, PinnedPlacementRefusesUnpinnedRegions) {
  Fixture f(spec_with({"memory.placement=pinned"}));
  f.map.add("buffer", Category::texture, kPage);
  f.build();
  EXPECT_THROW(f.run(0, 0, {{0, Category::texture, false}}), Error);
  EXPECT_THROW(f.mem->pin(0, 7), Error);
  Fixture g(spec_with({}));
  g.map.add("buffer", Category::texture, kPage);
  g.build();
  EXPECT_THROW(g.mem->pin(0, 1), Error) << "first-touch has no pins";
}

TEST(Memory, PreallocationCopiesOnceAndMakesReadsLocal) {
  Fixture f(spec_with({"memory.placement=preallocated"}));
  const uint32_t buf = f.map.add("buffer", Category::texture, 4 * kPage);
  const uint32_t fresh = f.map.add("fresh", Category::texture, kPage);
  f.build();
  const uint64_t base = f.map.region(buf).base;
  f.run(1, 0, reads(base, 4 * kPage));  // GPM 1 touches first: its home
  UnitTraffic p;
  EXPECT_EQ(f.mem->preallocate(base, 4 * kPage, 0, p), 4 * kPage);
  EXPECT_EQ(p.link_bytes[size_t(link_id(f.mem->topology(), 1, 0))], 4 * kPage);
  EXPECT_EQ(p.inter_gpm_bytes[size_t(Category::prealloc)], 4 * kPage);
  EXPECT_EQ(p.total_inter_gpm_bytes(), 4 * kPage) << "all of it counted as prealloc";
  UnitTraffic again;
  EXPECT_EQ(f.mem->preallocate(base, 4 * kPage, 0, again), 0u) << "data already there is not copied again";
  EXPECT_EQ(again.total_link_bytes(), 0u);
  const UnitTraffic& u = f.run(0, 0, reads(base, 4 * kPage));
  EXPECT_EQ(u.total_link_bytes(), 0u);
  EXPECT_EQ(u.dram_read_bytes[0], 4 * kPage);
  EXPECT_EQ(f.mem->resident_bytes()[0], 4 * kPage);
  EXPECT_EQ(f.mem->resident_bytes()[1], 4 * kPage);
  // Untouched data pre-allocated to a GPM is simply placed there.
  UnitTraffic q;
  EXPECT_EQ(f.mem->preallocate(f.map.region(fresh).base, kPage, 3, q), 0u);
  EXPECT_EQ(q.total_link_bytes(), 0u);
  EXPECT_EQ(f.mem->home_of(f.map.region(fresh).base), 3);
}

TEST(Memory, ConservationOfBytes) {
  // Every line read exactly once, from every GPM, over interleaved pages:
  // what each DRAM sends out equals what its requesters receive, and what a
  // link carries equals what its source delivered to its destination.
  Fixture f(spec_with({"memory.placement=interleaved"}));
  const uint32_t buf = f.map.add("buffer", Category::texture, 64 * kPage);
  f.build();
  const uint64_t lines = 64 * kPage / kLine;
  std::vector<uint64_t> order(lines);
  std::iota(order.begin(), order.end(), 0);
  Rng rng(3);
  for (uint64_t i = lines - 1; i > 0; --i) std::swap(order[i], order[rng.below(uint32_t(i + 1))]);
  for (uint64_t i = 0; i < lines; i += 97) {
    std::vector<LineAccess> chunk;
    for (uint64_t k = i; k < std::min(lines, i + 97); ++k)
      chunk.push_back({f.map.region(buf).base + order[k] * kLine, Category::texture, false});
    f.run(int(rng.below(4)), int(rng.below(8)), chunk);
  }
  const TrafficTotals& t = f.mem->totals();
  for (int h = 0; h < 4; ++h) {
    uint64_t delivered = 0;
    for (int g = 0; g < 4; ++g) delivered += t.delivered[size_t(h * 4 + g)];
    EXPECT_EQ(t.dram_read_bytes[size_t(h)][size_t(Category::texture)], delivered) << "DRAM " << h;
    for (int g = 0; g < 4; ++g) {
      if (g == h) continue;
      EXPECT_EQ(t.link_bytes[size_t(link_id(f.mem->topology(), h, g))][size_t(Category::texture)],
                t.delivered[size_t(h * 4 + g)]);
    }
  }
  EXPECT_EQ(t.dram_lines, lines);
  EXPECT_EQ(t.accesses, lines);
}

TEST(Memory, RingRoutesTakeTheShortestWay) {
  Fixture f(spec_with({"gpms=8", "link.topology=ring", "memory.placement=pinned"}));
  const uint32_t buf = f.map.add("buffer", Category::texture, kPage);
  f.build();
  const Topology& t = f.mem->topology();
  EXPECT_EQ(t.route(0, 1).size(), 1u);
  EXPECT_EQ(t.route(0, 3).size(), 3u);
  EXPECT_EQ(t.route(0, 5).size(), 3u) << "the other way round";
  EXPECT_EQ(t.route(0, 7).size(), 1u);
  EXPECT_EQ(t.route(0, 4).size(), 4u);
  EXPECT_EQ(t.link_name(t.route(0, 4)[0]), "gpm0->gpm1") << "ties go clockwise";
  // GPM 0 reading a page homed on GPM 3: the bytes cross 3->2, 2->1, 1->0.
  f.mem->pin(buf, 3);
  const UnitTraffic& u = f.run(0, 0, reads(f.map.region(buf).base, 4096));
  for (auto [a, b] : {std::pair{3, 2}, std::pair{2, 1}, std::pair{1, 0}})
    EXPECT_EQ(u.link_bytes[size_t(link_id(t, a, b))], 4096u) << a << "->" << b;
  EXPECT_EQ(u.total_link_bytes(), 3u * 4096);
  EXPECT_EQ(u.total_inter_gpm_bytes(), 4096u) << "one transfer, however many hops";
}

TEST(Memory, OneAccessMovesEachPeersLinesOverItsRouteOnce) {
  // One access reading two GPMs' pages and writing through to a third's,
  // interleaved, on an 8-GPM ring: each read crosses its home's route to
  // the requester, each write the requester's route to the home, and the
  // reads' hops are their routes' lengths (the memory system moves a
  // record's lines per peer and category at its end: MemorySystem::tally).
  Fixture f(spec_with({"gpms=8", "link.topology=ring", "memory.placement=pinned"}));
  const uint32_t a = f.map.add("a", Category::texture, kPage);
  const uint32_t b = f.map.add("b", Category::vertex, kPage);
  const uint32_t c = f.map.add("c", Category::colour, kPage);
  f.build();
  f.mem->pin(a, 3);
  f.mem->pin(b, 6);
  f.mem->pin(c, 2);
  std::vector<LineAccess> mixed;
  for (uint64_t at = 0; at < 2048; at += kLine) {
    mixed.push_back({f.map.region(a).base + at, Category::texture, false});
    mixed.push_back({f.map.region(c).base + at, Category::colour, true});
    if (at < 1024) mixed.push_back({f.map.region(b).base + at, Category::vertex, false});
  }
  const Topology& t = f.mem->topology();
  const UnitTraffic& u = f.run(0, 0, mixed);
  EXPECT_EQ(u.remote_hops, 16u * 3 + 8u * 2) << "3 hops from GPM 3, 2 from GPM 6";
  const auto on = [&](int from, int to) { return u.link_bytes[size_t(link_id(t, from, to))]; };
  for (auto [x, y] : {std::pair{3, 2}, std::pair{2, 1}, std::pair{1, 0}}) EXPECT_EQ(on(x, y), 2048u) << x << "->" << y;
  for (auto [x, y] : {std::pair{6, 7}, std::pair{7, 0}}) EXPECT_EQ(on(x, y), 1024u) << x << "->" << y;
  for (auto [x, y] : {std::pair{0, 1}, std::pair{1, 2}}) EXPECT_EQ(on(x, y), 2048u) << x << "->" << y;
  EXPECT_EQ(u.total_link_bytes(), 3u * 2048 + 2u * 1024 + 2u * 2048);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::texture)], 2048u);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::vertex)], 1024u);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::colour)], 2048u);
  const TrafficTotals& tot = f.mem->totals();
  EXPECT_EQ(tot.link_bytes[size_t(link_id(t, 1, 0))][size_t(Category::texture)], 2048u);
  EXPECT_EQ(tot.link_bytes[size_t(link_id(t, 7, 0))][size_t(Category::vertex)], 1024u);
  EXPECT_EQ(tot.link_bytes[size_t(link_id(t, 1, 2))][size_t(Category::colour)], 2048u);
  EXPECT_EQ(tot.moved[3 * 8 + 0], 2048u);
  EXPECT_EQ(tot.moved[6 * 8 + 0], 1024u);
  EXPECT_EQ(tot.moved[0 * 8 + 2], 2048u);
  EXPECT_EQ(tot.delivered[3 * 8 + 0], 2048u);
  EXPECT_EQ(tot.delivered[6 * 8 + 0], 1024u);
  EXPECT_EQ(tot.delivered[2 * 8 + 0], 0u) << "writes deliver nothing";
  // The next access starts from nothing: what this one moved is not moved again.
  const UnitTraffic& again = f.run(0, 1, reads(f.map.region(a).base, kLine));
  EXPECT_EQ(again.total_link_bytes(), 0u) << "served by GPM 0's remote cache";
  EXPECT_EQ(again.remote_hops, 0u);
}

TEST(Memory, SwitchRoutesTakeTwoHops) {
  Fixture f(spec_with({"gpms=16", "link.topology=switch"}));
  f.map.add("buffer", Category::texture, kPage);
  f.build();
  const Topology& t = f.mem->topology();
  EXPECT_EQ(t.links().size(), 32u);
  for (int a = 0; a < 16; ++a)
    for (int b = 0; b < 16; ++b) EXPECT_EQ(t.route(a, b).size(), a == b ? 0u : 2u);
  EXPECT_EQ(t.link_name(t.route(3, 9)[0]), "gpm3->switch0");
  EXPECT_EQ(t.link_name(t.route(3, 9)[1]), "switch0->gpm9");
}

TEST(Memory, RemoteWritesGoToTheHomeAndWriteBackOnEviction) {
  Fixture f(spec_with({"memory.placement=pinned", "cache.l2.size=16KB", "cache.l2.ways=4"}));
  const uint32_t fb = f.map.add("colour", Category::colour, 64 << 10);
  f.build();
  f.mem->pin(fb, 2);
  std::vector<LineAccess> w;
  for (uint64_t a = 0; a < (64u << 10); a += kLine) w.push_back({f.map.region(fb).base + a, Category::colour, true});
  const UnitTraffic& u = f.run(0, 0, w);
  EXPECT_EQ(u.link_bytes[size_t(link_id(f.mem->topology(), 0, 2))], 64u << 10);
  EXPECT_EQ(u.dram_read_bytes[2], 0u) << "write misses allocate without reading";
  // The home's 16 KB L2 keeps 128 of the 512 dirty lines; 384 were written back.
  EXPECT_EQ(u.dram_write_bytes[2], 384u * kLine);
  EXPECT_EQ(f.mem->totals().dram_write_bytes[2][size_t(Category::colour)], 384u * kLine);
}

TEST(Memory, ReplacementPolicies) {
  // One set of four ways: A B C D fill it, A is used again, E arrives.
  for (const char* policy : {"lru", "fifo"}) {
    CacheSpec s{{4 * kLine}, 4, policy};
    Cache c(s, kLine, "test");
    Cache::Eviction ev;
    for (uint64_t line : {10, 20, 30, 40}) EXPECT_FALSE(c.access(line, false, Category::texture, ev));
    EXPECT_TRUE(c.access(10, false, Category::texture, ev));
    EXPECT_FALSE(c.access(50, false, Category::texture, ev));
    if (std::string(policy) == "lru") {
      EXPECT_TRUE(c.contains(10)) << "recently used";
      EXPECT_FALSE(c.contains(20)) << "least recently used";
    } else {
      EXPECT_FALSE(c.contains(10)) << "first in";
      EXPECT_TRUE(c.contains(20));
    }
  }
  CacheSpec r{{4 * kLine}, 4, "random"};
  Cache a(r, kLine, "same-name"), b(r, kLine, "same-name");
  Cache::Eviction ev;
  for (uint64_t line = 0; line < 100; ++line) {
    a.access(line * 7, false, Category::texture, ev);
    b.access(line * 7, false, Category::texture, ev);
  }
  for (uint64_t line = 0; line < 100; ++line) EXPECT_EQ(a.contains(line * 7), b.contains(line * 7)) << "reproducible";
}

TEST(Memory, BadAccessesAreErrors) {
  Fixture f(spec_with({}));
  f.map.add("buffer", Category::texture, kPage);
  f.build();
  EXPECT_THROW(f.run(4, 0, {{0, Category::texture, false}}), Error);
  EXPECT_THROW(f.run(0, 8, {{0, Category::texture, false}}), Error);
  EXPECT_THROW(f.run(0, 0, {{kPage * 5, Category::texture, false}}), Error);
  UnitTraffic u;
  EXPECT_THROW(f.mem->preallocate(0, kPage * 9, 0, u), Error);
  EXPECT_THROW(f.mem->transfer(0, 9, 10, Category::composition, u), Error);
}

TEST(Memory, TransfersCountPerLinkAndPerCategory) {
  Fixture f(spec_with({"gpms=8", "link.topology=ring"}));
  f.map.add("buffer", Category::texture, kPage);
  f.build();
  UnitTraffic u;
  f.mem->transfer(1, 3, 1000, Category::composition, u);
  EXPECT_EQ(u.total_link_bytes(), 2000u);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::composition)], 1000u);
  f.mem->transfer(2, 2, 1000, Category::composition, u);
  EXPECT_EQ(u.inter_gpm_bytes[size_t(Category::composition)], 1000u) << "a GPM sending to itself crosses no link";
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

// Frame 5 of the scene's camera path, two 160x128 eyes, drawn with `p`.
FrameOutput small_frame(const Scene& scene, const PipelineSettings& p = {}) {
  StereoRig rig;
  rig.eye_width = 160;
  rig.eye_height = 128;
  return render_frame(scene, make_stereo_view(scene.camera, 5, rig), p);
}

TEST(Memory, SceneLayoutPlacesTraceLinesInsideTheirRegions) {
  const Scene scene = BuiltinScenes::find("courtyard")->make();
  const FrameOutput out = small_frame(scene);
  const MemorySpec spec = spec_with({});
  AddressMap map(spec.page, spec.line);
  const SceneLayout layout(map, scene, out.trace);
  ASSERT_FALSE(out.trace.tex_lines.empty());
  for (TexLine l : out.trace.tex_lines) {
    const Region& r = map.region(layout.texture_region(int(tex_line_texture(l))));
    const uint64_t a = layout.texture_line(l);
    EXPECT_GE(a, r.base);
    EXPECT_LT(a, r.base + r.bytes);
  }
  const Region& colour = map.region(layout.colour_region());
  EXPECT_EQ(layout.frame_line(layout.colour_region(), 0, 0, 0), colour.base);
  EXPECT_LT(layout.frame_line(layout.colour_region(), out.trace.tiles_x - 1, out.trace.tiles_y - 1, layout.lines_per_tile() - 1),
            colour.base + colour.bytes);
  // A trace recorded with other lines cannot be laid out against this map.
  PipelineSettings p;
  p.line_bytes = 64;
  const FrameOutput other = small_frame(scene, p);
  AddressMap map2(spec.page, spec.line);
  EXPECT_THROW(SceneLayout(map2, scene, other.trace), Error);
}

// FrameSim::replay hands a record's texture reads over as the trace lists
// them and the memory system finds their addresses: every answer is that of
// the same reads given as addresses, record by record, on a machine where
// reads go local and remote and framebuffer lines are read and written,
// with caches small enough that a record's lines evict one another (so
// their order shows).
TEST(Memory, TextureReadsAsTheTraceListsThemAnswerAsTheirAddressesDo) {
  const Scene scene = BuiltinScenes::find("courtyard")->make();
  const FrameOutput out = small_frame(scene);
  const MemorySpec spec = spec_with({"gpms=4", "memory.placement=interleaved", "cache.l1.size=1KB", "cache.l1.ways=2",
                                     "cache.l2.size=4KB", "cache.l2.ways=2", "cache.remote.size=2KB", "cache.remote.ways=2"});
  AddressMap map(spec.page, spec.line);
  const SceneLayout layout(map, scene, out.trace);
  MemorySystem listed(spec, map), addressed(spec, map);
  const int links = int(listed.topology().links().size());
  ASSERT_GT(out.trace.tiles.size(), 20u);
  // Everything an access answers, as one comparable (and printable) value.
  const auto answers = [](const UnitTraffic& u) {
    return std::make_tuple(u.accesses, u.l1_hits, u.l2_hits, u.remote_hits, u.home_l2_hits, u.dram_lines, u.l2_read_hits,
                           u.local_dram_reads, u.remote_dram_reads, u.remote_hops, u.dram_read_bytes, u.dram_write_bytes,
                           u.link_bytes, u.inter_gpm_bytes);
  };
  uint64_t reads = 0;
  for (size_t i = 0; i < out.trace.tiles.size(); ++i) {
    const TileWork& r = out.trace.tiles[i];
    const std::span<const TexLine> tex(out.trace.tex_lines.data() + r.tex_begin, r.tex_count);
    std::vector<LineAccess> frame;
    for (int l = 0; l < layout.lines_per_tile(); l += 3) {
      frame.push_back({layout.frame_line(layout.depth_region(), r.tile_x, r.tile_y, l), Category::depth, false});
      frame.push_back({layout.frame_line(layout.colour_region(), r.tile_x, r.tile_y, l), Category::colour, true});
    }
    std::vector<LineAccess> all;
    for (TexLine t : tex) all.push_back({layout.texture_line(t), Category::texture, false});
    all.insert(all.end(), frame.begin(), frame.end());
    const int gpm = int(i % 4), sm = int(i % uint64_t(spec.sms_per_gpm));
    const uint64_t repeats = i % 7;
    UnitTraffic a, b;
    a.reset(spec.gpms, links);
    b.reset(spec.gpms, links);
    listed.access(gpm, sm, layout, tex, frame, a, repeats);
    addressed.access(gpm, sm, all, b, repeats);
    reads += tex.size();
    ASSERT_EQ(a.accesses, tex.size() + frame.size() + repeats);
    EXPECT_EQ(answers(a), answers(b)) << "record " << i;
  }
  ASSERT_GT(reads, 1000u);
  const TrafficTotals &x = listed.totals(), &y = addressed.totals();
  EXPECT_GT(x.remote_hits + x.home_l2_hits, 0u);  // the remote paths were taken
  EXPECT_EQ(test::traffic_totals(x), test::traffic_totals(y));
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

TEST(Memory, EveryImplementationIsRegistered) {
  // A policy whose file exists but was not linked in would be missing here.
  // Each registry holds exactly what the files of its impl/ folder register.
  const auto placement = test::registered_in_sources("src/oovr/memory/placement/impl", "PlacementPolicies");
  const auto replacement = test::registered_in_sources("src/oovr/memory/replacement/impl", "ReplacementPolicies");
  const auto topologies = test::registered_in_sources("src/oovr/memory/topology/impl", "Topologies");
  ASSERT_GE(placement.size(), 5u);
  ASSERT_GE(replacement.size(), 3u);
  ASSERT_GE(topologies.size(), 3u);
  EXPECT_EQ(PlacementPolicies::names(), placement);
  EXPECT_EQ(ReplacementPolicies::names(), replacement);
  EXPECT_EQ(Topologies::names(), topologies);
}

}  // namespace
}  // namespace oovr

namespace oovr {
namespace {

// Where each read was served decides its latency (timing: requests in
// flight); writes are posted and count nowhere here.
TEST(Memory, ReadsAreCountedWhereTheyWereServed) {
  Fixture f(spec_with({"memory.placement=pinned"}));
  const uint32_t remote = f.map.add("remote", Category::texture, 8 << 10);
  const uint32_t local = f.map.add("local", Category::texture, 8 << 10);
  f.build();
  f.mem->pin(remote, 1);
  f.mem->pin(local, 0);
  const auto far = reads(f.map.region(remote).base, 8 << 10), near = reads(f.map.region(local).base, 8 << 10);
  UnitTraffic cold = f.run(0, 0, far);
  EXPECT_EQ(cold.remote_dram_reads, 64u);
  EXPECT_EQ(cold.remote_hops, 64u) << "one hop each on a fully connected system";
  EXPECT_EQ(cold.home_l2_hits + cold.l2_read_hits + cold.local_dram_reads, 0u);
  EXPECT_EQ(f.run(0, 1, far).remote_hits, 64u);
  f.mem->end_frame();
  const UnitTraffic warm = f.run(0, 2, far);
  EXPECT_EQ(warm.home_l2_hits, 64u);
  EXPECT_EQ(warm.remote_hops, 64u);
  EXPECT_EQ(f.run(0, 0, near).local_dram_reads, 64u);
  EXPECT_EQ(f.run(0, 1, near).l2_read_hits, 64u);
  std::vector<LineAccess> writes;
  for (const auto& a : near) writes.push_back({a.address, Category::colour, true});
  const UnitTraffic w = f.run(0, 3, writes);
  EXPECT_EQ(w.l2_read_hits + w.local_dram_reads + w.l1_hits, 0u);
  EXPECT_EQ(w.l2_hits, 64u) << "write hits count as L2 hits, not as reads";

  // Their latency, as the timing model charges it: a cold remote read pays
  // the remote-cache lookup, the link both ways, the home's L2 and DRAM.
  TimingEngine e;
  const MachineModel m(TimingSpec{}, f.spec, f.mem->topology(), e);
  const MemorySpec& s = f.spec;
  EXPECT_DOUBLE_EQ(m.read_latency(cold),
                   64 * (s.remote.latency.value + 2 * s.link_latency.value + s.l2.latency.value + s.dram_latency.value));
  EXPECT_DOUBLE_EQ(m.read_latency(warm), 64 * (s.remote.latency.value + 2 * s.link_latency.value + s.l2.latency.value));
}

// Copies made ahead of use share a capacity per GPM: the least recently
// used (or with FIFO the oldest) makes room; a batch never evicts its own
// copies, and what does not fit is not copied.
TEST(Memory, CopiesHaveACapacityAndTheLeastRecentlyUsedMakesRoom) {
  for (const char* eviction : {"lru", "fifo"}) {
    Fixture f(spec_with({"memory.placement=preallocated", "memory.copies.capacity=128KB",
                         (std::string("memory.copies.eviction=") + eviction).c_str()}));
    std::vector<uint64_t> base;
    for (const char* name : {"a", "b", "c"}) base.push_back(f.map.region(f.map.add(name, Category::texture, kPage)).base);
    f.build();
    for (uint64_t b : base) f.run(1, 0, reads(b, kPage));  // homes on GPM 1
    UnitTraffic t;
    f.mem->begin_batch();
    f.mem->preallocate(base[0], kPage, 0, t);
    f.mem->begin_batch();
    f.mem->preallocate(base[1], kPage, 0, t);
    f.run(0, 0, {{base[0], Category::texture, false}});  // a is read again: b is now the least recently used
    f.mem->begin_batch();
    EXPECT_EQ(f.mem->preallocate(base[2], kPage, 0, t), kPage);
    const bool lru = std::string(eviction) == "lru";
    EXPECT_EQ(f.mem->holds(0, base[0]), lru) << eviction;
    EXPECT_EQ(f.mem->holds(0, base[1]), !lru) << eviction;
    EXPECT_TRUE(f.mem->holds(0, base[2])) << eviction;
    EXPECT_EQ(f.mem->copy_bytes(0), 2 * kPage);
    EXPECT_EQ(f.mem->resident_bytes()[0], 2 * kPage) << "the footprint is bounded";
    EXPECT_EQ(f.mem->totals().copies_evicted, 1u);
    // One batch asking for all three: its own copies stay, the third is not made.
    f.mem->begin_batch();
    UnitTraffic all;
    // LRU holds a and c: a stays, c makes room for b. FIFO holds b and c:
    // both make room, for a and b.
    EXPECT_EQ(f.mem->preallocate(base[0], 3 * kPage, 0, all), lru ? kPage : 2 * kPage) << eviction;
    EXPECT_EQ(f.mem->copy_bytes(0), 2 * kPage);
    EXPECT_EQ(f.mem->totals().copies_refused, 1u);
  }
}

// Copies live in what a GPM's homes leave of its DRAM (dram.capacity): the
// DRAM bounds them with no cap set, a new home takes the room of a copy
// (the least recently used), and homes beyond the DRAM are an error naming
// the GPM. Worked by hand in 64 KB pages on a 4-page DRAM.
TEST(Memory, CopiesLiveInTheDramTheHomesLeave) {
  Fixture f(spec_with({"memory.placement=preallocated", "dram.capacity=256KB"}));
  std::vector<uint64_t> base;
  for (const char* name : {"a", "b", "c", "d", "e", "g", "h"})
    base.push_back(f.map.region(f.map.add(name, Category::texture, kPage)).base);
  f.build();
  for (int k = 0; k < 4; ++k) f.run(1, 0, reads(base[size_t(k)], kPage));  // a-d homed on GPM 1: its DRAM is full
  f.run(0, 0, reads(base[4], kPage));                                      // e homed on GPM 0: 3 pages left for copies
  EXPECT_EQ(f.mem->homed_bytes(0), kPage);
  EXPECT_EQ(f.mem->homed_bytes(1), 4 * kPage);
  UnitTraffic t;
  for (int k = 0; k < 4; ++k) {  // a, b, c, then d: a (least recently used) makes room
    f.mem->begin_batch();
    EXPECT_EQ(f.mem->preallocate(base[size_t(k)], kPage, 0, t), kPage) << k;
  }
  EXPECT_FALSE(f.mem->holds(0, base[0]));
  EXPECT_TRUE(f.mem->holds(0, base[3]));
  EXPECT_EQ(f.mem->copy_bytes(0), 3 * kPage);
  EXPECT_EQ(f.mem->copy_peak_bytes(0), 3 * kPage);
  EXPECT_EQ(f.mem->totals().copies_evicted, 1u);
  // A new home on GPM 0 takes the room of its least recently used copy, b.
  f.run(0, 0, reads(base[5], kPage));
  EXPECT_EQ(f.mem->homed_bytes(0), 2 * kPage);
  EXPECT_EQ(f.mem->copy_bytes(0), 2 * kPage);
  EXPECT_FALSE(f.mem->holds(0, base[1]));
  EXPECT_TRUE(f.mem->holds(0, base[2]) && f.mem->holds(0, base[3]));
  EXPECT_EQ(f.mem->totals().copies_evicted, 2u);
  // GPM 1 is full of homes: one more is an error naming it and the key.
  EXPECT_EQ(test::message_of([&] { f.run(1, 0, reads(base[6], kPage)); }),
            "GPM 1's DRAM (dram.capacity = 256 KB) cannot hold the data placed there: 320 KB of buffers, textures and "
            "framebuffers");
  // The cap, when set, bounds the copies below what the DRAM leaves.
  Fixture capped(spec_with({"memory.placement=preallocated", "dram.capacity=8GB", "memory.copies.capacity=64KB"}));
  const uint64_t x = capped.map.region(capped.map.add("x", Category::texture, 2 * kPage)).base;
  capped.build();
  capped.run(1, 0, reads(x, 2 * kPage));
  capped.mem->begin_batch();
  UnitTraffic c;
  EXPECT_EQ(capped.mem->preallocate(x, 2 * kPage, 0, c), kPage);
  EXPECT_EQ(capped.mem->totals().copies_refused, 1u);
}

TEST(Memory, TheEndOfADrawOnOneGpmDropsOnlyItsRemoteCache) {
  Fixture f(spec_with({"memory.placement=pinned", "cache.remote.invalidate=draw"}));
  const uint32_t tex = f.map.add("texture", Category::texture, 8 << 10);
  f.build();
  f.mem->pin(tex, 1);
  const auto all = reads(f.map.region(tex).base, 8 << 10);
  f.run(0, 0, all);
  f.run(2, 0, all);
  f.mem->end_draw(0);
  EXPECT_EQ(f.run(0, 1, all).remote_hits, 0u);
  EXPECT_EQ(f.run(2, 1, all).remote_hits, 64u);
  EXPECT_THROW(f.mem->end_draw(9), Error);
}

// Energy (docs/model.md, "Energy"): every lookup of a cache, hit or miss,
// costs a line's bits at the level's energy per bit; a DRAM's and a link's
// bytes cost theirs. Counted here by hand for four kinds of access.
TEST(Memory, EnergyIntegratesEachLevelsLookupsAndEachLinksBytes) {
  for (const bool between_nodes : {false, true}) {
    Fixture f(between_nodes ? spec_with({"memory.placement=pinned", "link.energy_per_bit=250pJ"})
                            : spec_with({"memory.placement=pinned"}));
    const uint32_t far = f.map.add("far", Category::texture, 8 << 10);
    const uint32_t near = f.map.add("near", Category::colour, 8 << 10);
    f.build();
    f.mem->pin(far, 1);
    f.mem->pin(near, 0);
    const auto texels = reads(f.map.region(far).base, 8 << 10);
    f.run(0, 0, texels);  // 64 lines: L1 misses, remote-cache misses, GPM 1's L2 misses, its DRAM, link 1->0
    f.run(0, 0, texels);  // 64 L1 hits
    f.run(1, 0, texels);  // GPM 1's own: 64 L1 misses, 64 L2 hits
    std::vector<LineAccess> writes;
    for (const auto& a : reads(f.map.region(near).base, 8 << 10)) writes.push_back({a.address, Category::colour, true});
    f.run(0, 1, writes);  // no L1; 64 lookups of GPM 0's L2, no DRAM until written back
    SchemeResult r;
    f.mem->report(r.stats);
    EXPECT_EQ(r.stats.at("l1", "lookups"), 192);
    EXPECT_EQ(r.stats.at("l2", "lookups"), 192);
    EXPECT_EQ(r.stats.at("remote_cache", "lookups"), 64);
    const double line_bits = 1024, j = 1e-12;
    const double caches = 192 * line_bits * 0.21875 * j + (192 + 64) * line_bits * 1.5625 * j;
    const double dram = (8 << 10) * 8 * 14 * j, links = (8 << 10) * 8 * (between_nodes ? 250 : 10) * j;
    const Energy e = energy_of(r);
    EXPECT_TRUE(e.known);
    EXPECT_NEAR(e.caches, caches, 1e-9 * caches);
    EXPECT_NEAR(e.dram, dram, 1e-9 * dram);
    EXPECT_NEAR(e.links, links, 1e-9 * links);
    EXPECT_NEAR(energy_at(r, "gpm[1].dram"), dram, 1e-9 * dram);
    EXPECT_EQ(energy_at(r, "gpm[0].dram"), 0);
    EXPECT_NEAR(energy_at(r, "link[1->0]"), links, 1e-9 * links);
    EXPECT_TRUE(std::isnan(energy_at(r, "memory")));
    // Every output reads the same figures: the frame's total and parts,
    // each location's energy after its price.
    double total = 0, located = 0;
    for (const Metric& m : metrics_of(r)) {
      if (m.location == "frame" && m.metric == "energy") total = m.value;
      if (m.location != "frame" && m.metric == "energy") located += m.value;
      if (m.metric == "energy") {
        EXPECT_EQ(m.unit, "J");
      }
    }
    EXPECT_NEAR(total, caches + dram + links, 1e-9 * total);
    EXPECT_NEAR(located, total, 1e-9 * total);
  }
  // Energies are read as energies, in range.
  EXPECT_EQ(spec_with({"dram.energy_per_bit=3.97pJ"}).dram_energy_per_bit.value, 3.97 / 1e12);
  EXPECT_EQ(spec_with({"cache.l1.energy_per_bit=0pJ"}).l1.energy_per_bit.value, 0);
  for (const char* bad :
       {"link.energy_per_bit=-1pJ", "link.energy_per_bit=1J", "link.energy_per_bit=10", "dram.energy_per_bit=10pW"})
    EXPECT_THROW(spec_with({bad}), Error) << bad;
}

}  // namespace
}  // namespace oovr
