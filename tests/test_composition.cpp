// Composition algorithms (schemes/composition.h) on every sort-last scheme
// that takes one. The bytes each algorithm sends are worked out here from
// the frame's trace by the algorithm's definition, with plain arrays (no
// code of the Composer's): which GPM shaded each record (the run's owner
// log), the final frame's owner of its tile, and the lines each GPM holds.
#include <gtest/gtest.h>

#include <bit>

#include "oovr/memory/category.h"
#include "oovr/schemes/composition.h"
#include "oovr/schemes/i_scheme.h"
#include "oovr/schemes/sort_first.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& crowd() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("crowd", 96, 64, 3, 1);
  return *r;
}

SchemeResult run(const char* scheme, int gpms, const char* algorithm) {
  Config c;
  c.set("gpms", std::to_string(gpms));
  if (algorithm) c.set("sort_last.composition", algorithm);
  const auto& r = crowd();
  return run_scheme(scheme, r.scene, {r.traces[0]}, c);
}

TEST(Composition, BisectionHalvesTheLongerSide) {
  // 8 x 4 tiles in 4: columns 0-1, 2-3, 4-5, 6-7.
  const std::vector<int> four = bisected_owners(8, 4, 4);
  for (int ty = 0; ty < 4; ++ty)
    for (int tx = 0; tx < 8; ++tx) EXPECT_EQ(four[size_t(ty * 8 + tx)], tx / 2) << tx << "," << ty;
  // 6 x 2 in 3: the first part gets a third (columns 0-1), the other two
  // halve the rest (2-3, 4-5).
  const std::vector<int> three = bisected_owners(6, 2, 3);
  EXPECT_EQ(three, (std::vector<int>{0, 0, 1, 1, 2, 2, 0, 0, 1, 1, 2, 2}));
  // 2 x 8 in 4: bands of two rows.
  const std::vector<int> tall = bisected_owners(2, 8, 4);
  for (int ty = 0; ty < 8; ++ty) EXPECT_EQ(tall[size_t(ty * 2)], ty / 2) << ty;
}

// Lines each GPM holds per tile, from the records it shaded (a tile's
// colour lines, ORed), and what the algorithms send.
struct Model {
  const FrameTrace& f;
  int n;
  std::vector<std::vector<uint32_t>> held;  // [gpm][tile]: lines, tiles it does not own
  std::vector<int> owner;                   // [tile]

  Model(const FrameTrace& frame, const SchemeResult& r, int gpms, std::vector<int> owners)
      : f(frame), n(gpms), held(size_t(gpms), std::vector<uint32_t>(owners.size(), 0)), owner(std::move(owners)) {
    for (const TileWork& w : f.tiles) {
      const uint32_t tile = uint32_t(w.tile_y) * uint32_t(f.tiles_x) + w.tile_x;
      const int g = r.owner_of(w.object, tile);
      EXPECT_GE(g, 0);
      if (g >= 0 && g != owner[tile]) held[size_t(g)][tile] |= w.colour_write_mask;
    }
  }
  uint64_t bytes(uint32_t lines) const { return uint64_t(std::popcount(lines)) * f.line_bytes; }

  // Every GPM sends its lines of each tile to the tile's owner once.
  uint64_t pairwise() const {
    uint64_t b = 0;
    for (const auto& h : held)
      for (uint32_t lines : h) b += bytes(lines);
    return b;
  }
  // Fold GPMs p.. into g - p, then swap halves: in the round of bit `bit`,
  // GPM g sends what it holds of tiles whose owner differs from g in that
  // bit, and its partner ORs them into its own (or, at the owner, keeps
  // them in the final frame).
  uint64_t binary_swap() {
    const int p = int(std::bit_floor(unsigned(n)));
    uint64_t b = 0;
    const auto give = [&](int from, int to, const std::vector<bool>& tiles) {
      for (size_t t = 0; t < owner.size(); ++t)
        if (tiles[t] && held[size_t(from)][t]) {
          b += bytes(held[size_t(from)][t]);
          if (owner[t] != to) held[size_t(to)][t] |= held[size_t(from)][t];
          held[size_t(from)][t] = 0;
        }
    };
    for (int g = p; g < n; ++g) give(g, g - p, std::vector<bool>(owner.size(), true));
    for (int bit = p / 2; bit >= 1; bit /= 2) {
      std::vector<std::vector<bool>> out(size_t(p), std::vector<bool>(owner.size(), false));
      for (int g = 0; g < p; ++g)
        for (size_t t = 0; t < owner.size(); ++t) out[size_t(g)][t] = ((owner[t] ^ g) & bit) != 0;
      // Take every packet before any lands.
      std::vector<std::vector<uint32_t>> packets(size_t(p), std::vector<uint32_t>(owner.size(), 0));
      for (int g = 0; g < p; ++g)
        for (size_t t = 0; t < owner.size(); ++t)
          if (out[size_t(g)][t]) std::swap(packets[size_t(g)][t], held[size_t(g)][t]);
      for (int g = 0; g < p; ++g)
        for (size_t t = 0; t < owner.size(); ++t)
          if (packets[size_t(g)][t]) {
            b += bytes(packets[size_t(g)][t]);
            if (owner[t] != (g ^ bit)) held[size_t(g ^ bit)][t] |= packets[size_t(g)][t];
          }
    }
    return b;
  }
};

uint64_t composition_bytes(const SchemeResult& r) { return r.inter_gpm_bytes[size_t(Category::composition)]; }

std::vector<int> strips(const FrameTrace& f, int n) {
  std::vector<int> o(size_t(f.tiles_x) * size_t(f.tiles_y));
  for (int ty = 0; ty < f.tiles_y; ++ty)
    for (int tx = 0; tx < f.tiles_x; ++tx)
      o[size_t(ty) * size_t(f.tiles_x) + size_t(tx)] = vertical_strip_owner(tx, f.tiles_x, n);
  return o;
}

// Gather and direct send send each record's lines to the owner as the
// record's piece of work ends (no merging on the way).
uint64_t per_record(const FrameTrace& f, const SchemeResult& r, const std::vector<int>& owner) {
  uint64_t b = 0;
  for (const TileWork& w : f.tiles) {
    const uint32_t tile = uint32_t(w.tile_y) * uint32_t(f.tiles_x) + w.tile_x;
    if (r.owner_of(w.object, tile) != owner[tile]) b += uint64_t(std::popcount(w.colour_write_mask)) * f.line_bytes;
  }
  return b;
}

TEST(Composition, EachAlgorithmSendsTheLinesItsDefinitionSays) {
  const FrameTrace& f = *crowd().traces[0];
  for (const char* scheme : {"object", "oo-app", "oo-vr", "chopin"})
    for (int n : {2, 3, 4}) {
      SCOPED_TRACE(std::string(scheme) + " at " + std::to_string(n) + " GPMs");
      const SchemeResult gather = run(scheme, n, "gather");
      EXPECT_EQ(composition_bytes(gather), per_record(f, gather, std::vector<int>(size_t(f.tiles_x * f.tiles_y), 0)));
      const SchemeResult direct = run(scheme, n, "direct-send");
      EXPECT_EQ(composition_bytes(direct), per_record(f, direct, strips(f, n)));
      const SchemeResult pair = run(scheme, n, "pairwise");
      EXPECT_EQ(composition_bytes(pair), Model(f, pair, n, bisected_owners(f.tiles_x, f.tiles_y, n)).pairwise());
      const SchemeResult swap = run(scheme, n, "binary-swap");
      const int p = int(std::bit_floor(unsigned(n)));
      Model m(f, swap, n, bisected_owners(f.tiles_x, f.tiles_y, p));
      EXPECT_EQ(composition_bytes(swap), m.binary_swap());
      EXPECT_GT(composition_bytes(swap), 0u);
      // Merging lines on the way: pairwise sends each GPM's union of lines
      // once, never more than a record at a time would.
      EXPECT_LE(composition_bytes(pair), per_record(f, pair, bisected_owners(f.tiles_x, f.tiles_y, n)));
    }
}

// Each scheme's own: object-level and OO_APP gather to the root, OO-VR
// sends directly to its strips (DHC).
TEST(Composition, TheSchemesOwnAlgorithmIsTheDefault) {
  for (const auto& [scheme, algorithm] :
       {std::pair{"object", "gather"}, {"oo-app", "gather"}, {"oo-vr", "direct-send"}, {"chopin", "pairwise"}}) {
    const SchemeResult own = run(scheme, 4, nullptr), named = run(scheme, 4, algorithm);
    EXPECT_EQ(composition_bytes(own), composition_bytes(named)) << scheme;
    EXPECT_EQ(own.frame_latency_s, named.frame_latency_s) << scheme;
  }
}

// Two GPMs: binary swap and pairwise are one exchange of halves.
TEST(Composition, TwoGpmsSwapAsPairwiseDoes) {
  const SchemeResult swap = run("object", 2, "binary-swap"), pair = run("object", 2, "pairwise");
  EXPECT_EQ(composition_bytes(swap), composition_bytes(pair));
  EXPECT_GT(composition_bytes(swap), 0u);
}

// A bad name is refused naming the key and the choices (a sweep refuses
// the key for a scheme that takes no algorithm: test_sweep.cpp).
TEST(Composition, ABadAlgorithmIsRefusedNamingTheKey) {
  const std::string bad = test::message_of([] { (void)run("object", 4, "tree"); });
  EXPECT_NE(bad.find("sort_last.composition"), std::string::npos) << bad;
  EXPECT_NE(bad.find("binary-swap"), std::string::npos) << bad;
}

}  // namespace
}  // namespace oovr
