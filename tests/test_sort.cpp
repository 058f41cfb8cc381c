#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "oovr/core/rng.h"
#include "oovr/core/sort.h"

namespace oovr {
namespace {

using Entry = std::pair<std::pair<uint32_t, uint32_t>, int>;

// Entries as a run's owner log holds them: keys of a few objects and tiles,
// many of them repeated, each entry's place in the log as its value, so
// that an order broken within a key shows.
std::vector<Entry> log_of(uint64_t seed, size_t n, uint32_t objects, uint32_t tiles) {
  Rng rng(seed);
  std::vector<Entry> v;
  for (size_t i = 0; i < n; ++i) v.push_back({{uint32_t(rng.next() % objects), uint32_t(rng.next() % tiles)}, int(i)});
  return v;
}

TEST(Sort, PairsSortAsAStableSortWouldWhateverTheirKeys) {
  // Small keys (the counting passes), keys up to 2^32 - 1 (the fallback),
  // short logs, and logs of one key.
  const struct {
    size_t n;
    uint32_t objects, tiles;
  } cases[] = {{0, 1, 1},
               {1, 1, 1},
               {63, 5, 9},
               {64, 5, 9},
               {1000, 1, 1},
               {1000, 7, 3},
               {5000, 300, 5120},
               {5000, 5120, 300},
               {20000, 2000, 10240},
               {300, 4000000000u, 7},
               {300, 7, 4000000000u},
               {70000, 70000, 70000},
               {4000, 81536, 3}};
  uint64_t seed = 1;
  for (const auto& c : cases)
    for (int k = 0; k < 3; ++k) {
      std::vector<Entry> v = log_of(seed++, c.n, c.objects, c.tiles);
      std::vector<Entry> want = v;
      std::stable_sort(want.begin(), want.end(), [](const Entry& a, const Entry& b) { return a.first < b.first; });
      stable_sort_by_pair(v);
      EXPECT_EQ(v, want) << c.n << " entries of " << c.objects << " objects and " << c.tiles << " tiles";
    }
}

}  // namespace
}  // namespace oovr
