// The FrameTrace against the image it describes, its ordering and ranges,
// and determinism across thread counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include <map>
#include <tuple>

#include "oovr/core/hash.h"
#include "oovr/core/rng.h"
#include "oovr/scene/builtin.h"
#include "test_util.h"
#include "texture_records.h"

namespace oovr {
namespace {

struct Rendered {
  Scene scene;
  StereoView view;
  FrameOutput out;
};

Rendered render_builtin(const std::string& name, int frame, unsigned threads, int eye_w = 160, int eye_h = 128) {
  Rendered r{BuiltinScenes::find(name)->make(), {}, {}};
  StereoRig rig;
  rig.eye_width = eye_w;
  rig.eye_height = eye_h;
  r.view = make_stereo_view(r.scene.camera, frame, rig);
  PipelineSettings p;
  p.threads = threads;
  r.out = render_frame(r.scene, r.view, p, frame);
  return r;
}

TEST(Trace, CountsMatchTheImage) {
  const Rendered r = render_builtin("courtyard", 10, 2);
  const FrameTrace& t = r.out.trace;
  // Pixels finally showing object o were written by one of o's passed
  // fragments, so they never outnumber them.
  std::vector<uint64_t> shown(r.scene.objects.size(), 0), passed(r.scene.objects.size(), 0), covered(r.scene.objects.size(), 0);
  for (uint32_t id : r.out.object_id)
    if (id != kNoObject) ++shown[id];
  for (const auto& w : t.tiles) {
    passed[w.object] += w.passed;
    covered[w.object] += w.covered;
    EXPECT_LE(w.passed, w.shaded);
    EXPECT_LE(w.shaded, w.covered);
    EXPECT_LE(w.quads, w.shaded);  // a shaded quad has at least one shaded fragment
    EXPECT_LE(w.shaded, 4u * w.quads);
    EXPECT_GT(w.triangles, 0u);
    EXPECT_LE(w.vertices, 3u * w.triangles);
  }
  uint64_t shown_total = 0;
  for (size_t o = 0; o < shown.size(); ++o) {
    EXPECT_LE(shown[o], passed[o]) << r.scene.objects[o].name;
    shown_total += shown[o];
  }
  // The ground is drawn first over an empty frame: every fragment it covers passes.
  ASSERT_EQ(r.scene.objects[0].name, "ground");
  EXPECT_EQ(passed[0], covered[0]);
  EXPECT_GT(shown_total, 0u);
  EXPECT_LE(shown_total, uint64_t(r.view.frame_width) * r.view.frame_height);
}

TEST(Trace, WriteMasksCoverEveryWrittenPixel) {
  const Rendered r = render_builtin("crowd", 3, 2);
  const FrameTrace& t = r.out.trace;
  std::map<std::tuple<uint32_t, int, int>, uint32_t> masks;  // (object, tile x, tile y) -> lines written
  for (const auto& w : t.tiles) masks[{w.object, w.tile_x, w.tile_y}] |= w.colour_write_mask;
  const int per_row = kTileSize / t.block_w;
  for (int y = 0; y < t.frame_height; ++y)
    for (int x = 0; x < t.frame_width; ++x) {
      const uint32_t id = r.out.object_id[size_t(y) * t.frame_width + x];
      if (id == kNoObject) continue;
      const int lx = x % kTileSize, ly = y % kTileSize;
      const uint32_t line = uint32_t((ly / t.block_h) * per_row + lx / t.block_w);
      const auto it = masks.find({id, x / kTileSize, y / kTileSize});
      ASSERT_NE(it, masks.end());
      EXPECT_TRUE(it->second & (1u << line)) << x << "," << y;
    }
}

TEST(Trace, SortedWithContiguousTextureRanges) {
  const Rendered r = render_builtin("courtyard", 0, 2);
  const FrameTrace& t = r.out.trace;
  ASSERT_FALSE(t.tiles.empty());
  uint64_t next = 0;
  for (size_t i = 0; i < t.tiles.size(); ++i) {
    const TileWork& w = t.tiles[i];
    EXPECT_EQ(w.tex_begin, next);
    next += w.tex_count;
    if (i > 0) {
      const TileWork& p = t.tiles[i - 1];
      EXPECT_LT(std::make_tuple(p.object, p.eye, p.tile_y, p.tile_x), std::make_tuple(w.object, w.eye, w.tile_y, w.tile_x));
    }
    EXPECT_LT(w.tile_x, t.tiles_x);
    EXPECT_LT(w.tile_y, t.tiles_y);
  }
  EXPECT_EQ(next, t.tex_lines.size());
  for (TexLine l : t.tex_lines) EXPECT_LT(tex_line_texture(l), r.scene.textures.size());
}

bool same_trace(const FrameTrace& a, const FrameTrace& b) {
  return a.tiles == b.tiles && a.objects == b.objects && a.tex_lines == b.tex_lines;
}

TEST(Trace, IdenticalWhateverTheThreadCount) {
  const Rendered one = render_builtin("courtyard", 20, 1, 320, 256);
  for (unsigned threads : {2u, 3u, 8u}) {
    const Rendered many = render_builtin("courtyard", 20, threads, 320, 256);
    EXPECT_EQ(one.out.colour.rgba, many.out.colour.rgba) << threads << " threads";
    EXPECT_EQ(one.out.object_id, many.out.object_id) << threads << " threads";
    EXPECT_TRUE(same_trace(one.out.trace, many.out.trace)) << threads << " threads";
  }
}

TEST(Trace, LineBlockShapes) {
  int w = 0, h = 0;
  line_block_shape(128, w, h);
  EXPECT_EQ(w * 10 + h, 84);
  line_block_shape(64, w, h);
  EXPECT_EQ(w * 10 + h, 44);
  line_block_shape(32, w, h);
  EXPECT_EQ(w * 10 + h, 42);
  line_block_shape(1024, w, h);
  EXPECT_EQ(w * 100 + h, 1616);
}

TEST(Trace, TextureLinesWithoutTheirRepeatsWithinARecord) {
  // Two records; lines named (texture, index); modulus 4, so indices 1 and 5
  // share a residue. Record 0: a a b a(5) a a -> a, b, a(5), a are kept
  // (the last a follows a(5) of its residue); record 1 starts afresh.
  FrameTrace t;
  const TexLine a = make_tex_line(0, 1), b = make_tex_line(0, 2), a5 = make_tex_line(0, 5), c = make_tex_line(1, 1);
  for (TexLine l : {a, a, b, a5, a, a, /* record 1 */ a, c, c, a, b, b}) t.tex_lines.push_back(l);
  t.tiles.resize(3);
  t.tiles[0].tex_begin = 0;
  t.tiles[0].tex_count = 6;
  t.tiles[1].tex_begin = 6;
  t.tiles[1].tex_count = 0;  // a record that samples nothing
  t.tiles[2].tex_begin = 6;
  t.tiles[2].tex_count = 6;
  // Kept: 0: a b a5 a; 1: none; 2: a c a b (c, then a: index 1 both, texture
  // differs). 8 of 12 lines stay, at least half: not kept at all.
  EXPECT_EQ(t.tex_lines_without_repeats(4), nullptr);
  // With repeats the majority: a record of 12 reads of one line, twice.
  FrameTrace r;
  for (int i = 0; i < 24; ++i) r.tex_lines.push_back(i < 12 ? a : b);
  r.tiles.resize(2);
  r.tiles[0].tex_count = 12;
  r.tiles[1].tex_begin = 12;
  r.tiles[1].tex_count = 12;
  const auto w = r.tex_lines_without_repeats(4);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->modulus, 4u);
  EXPECT_EQ(w->lines, (std::vector<TexLine>{a, b}));
  EXPECT_EQ(w->begin, (std::vector<uint64_t>{0, 1, 2}));
  EXPECT_EQ(r.tex_lines_without_repeats(4), w);  // derived once
  // Another modulus, its own; a changed trace (storage or size) anew.
  EXPECT_NE(r.tex_lines_without_repeats(8), w);
  FrameTrace copy = r;
  EXPECT_NE(copy.tex_lines_without_repeats(4), w);
  EXPECT_EQ(copy.tex_lines_without_repeats(4)->lines, w->lines);
  // t's 8 of 12 with its repeats in the majority: ten more reads of c.
  for (int i = 0; i < 10; ++i) t.tex_lines.push_back(c);
  t.tiles[2].tex_count = 16;
  const auto v = t.tex_lines_without_repeats(4);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->lines, (std::vector<TexLine>{a, b, a5, a, a, c, a, b, c}));
  EXPECT_EQ(v->begin, (std::vector<uint64_t>{0, 4, 4, 9}));
  EXPECT_THROW((void)t.tex_lines_without_repeats(3), Error);
  EXPECT_THROW((void)t.tex_lines_without_repeats(0), Error);
}

TEST(Trace, TheRecordsChecksumIsTheirBytesAndFollowsAChangedTrace) {
  // A memory tape is played only on the frames it was recorded on: their
  // records' checksum, kept on the trace, must be that of the records as
  // they are when it is asked for.
  FrameTrace t;
  t.tiles.resize(3);
  t.tiles[1].tex_count = 7;
  const auto bytes = [](const FrameTrace& f) {
    return checksum64({reinterpret_cast<const char*>(f.tiles.data()), f.tiles.size() * sizeof(TileWork)});
  };
  const uint64_t first = t.records_checksum();
  EXPECT_EQ(first, bytes(t));
  EXPECT_EQ(t.records_checksum(), first);  // kept
  // A copy sums its own; another record (new storage and size) anew.
  FrameTrace copy = t;
  copy.tiles[1].tex_count = 8;
  EXPECT_EQ(copy.records_checksum(), bytes(copy));
  EXPECT_NE(copy.records_checksum(), first);
  t.tiles.push_back(t.tiles[1]);
  EXPECT_EQ(t.records_checksum(), bytes(t));
  EXPECT_NE(t.records_checksum(), first);
}

TEST(Trace, TextureLinesWithoutTheirSureHitsInAnLruCache) {
  // One set (indices 0, 4, 8 modulo 4). Record 0 alternates A and B: with
  // LRU of 4 ways every read after the first two is a sure hit, and all but
  // the last read of each line are left out (A B A B); without LRU nothing
  // is (no read repeats the one before). Record 1: A B A C A keeps all: C
  // may miss between the A's, so the middle A's use is kept. Record 2: 30
  // reads of A, the first kept. Record 3: A B C D E A E A keeps all: the
  // second A follows four other lines of the set (stack distance 4), so it
  // may miss, and is no sure hit to leave out for the third.
  FrameTrace t;
  const TexLine a = make_tex_line(0, 0), b = make_tex_line(0, 4), c = make_tex_line(1, 8), d = make_tex_line(1, 12),
                e = make_tex_line(0, 16);
  for (TexLine l : {a, b, a, b, a, b, a, b, a, b}) t.tex_lines.push_back(l);
  for (TexLine l : {a, b, a, c, a}) t.tex_lines.push_back(l);
  for (int i = 0; i < 30; ++i) t.tex_lines.push_back(a);
  for (TexLine l : {a, b, c, d, e, a, e, a}) t.tex_lines.push_back(l);
  t.tiles.resize(4);
  t.tiles[0].tex_count = 10;
  t.tiles[1].tex_begin = 10;
  t.tiles[1].tex_count = 5;
  t.tiles[2].tex_begin = 15;
  t.tiles[2].tex_count = 30;
  t.tiles[3].tex_begin = 45;
  t.tiles[3].tex_count = 8;
  const auto lru = t.tex_lines_without_repeats(4, 4);
  ASSERT_NE(lru, nullptr);
  EXPECT_EQ(lru->lru_ways, 4);
  EXPECT_EQ(lru->lines, (std::vector<TexLine>{a, b, a, b, a, b, a, c, a, a, a, b, c, d, e, a, e, a}));
  EXPECT_EQ(lru->begin, (std::vector<uint64_t>{0, 4, 9, 10, 18}));
  const auto any = t.tex_lines_without_repeats(4);
  ASSERT_NE(any, nullptr);
  EXPECT_EQ(any->lines.size(), 24u);  // 10 + 5 + 1 + 8
  EXPECT_NE(any, lru);
  // With 1 way nothing after the first of each is sure.
  // With 5 ways record 3's second A is a sure hit, read again after E (a
  // sure hit too): left out.
  std::vector<TexLine> five = lru->lines;
  five.erase(five.begin() + 15);
  EXPECT_EQ(t.tex_lines_without_repeats(4, 5)->lines, five);
  // With 2 ways record 0 is as with 4; record 3 keeps all.
  EXPECT_EQ(t.tex_lines_without_repeats(4, 2)->lines, lru->lines);
  EXPECT_EQ(t.tex_lines_without_repeats(4, 1)->lines, any->lines);
  EXPECT_THROW((void)t.tex_lines_without_repeats(4, -1), Error);
  EXPECT_THROW((void)t.tex_lines_without_repeats(uint64_t(1) << 20, 16), Error);  // 17 M lines of scratch
}

// The rules of FrameTrace::tex_lines_without_repeats as they are stated,
// for one record of `lines` in `sets` sets: a read of the line its set last
// read in the record is left out; with LRU of `ways` ways (0: none), a read
// is a sure hit where its line was read in the record with fewer than
// `ways` other lines of its set read since, and a sure hit is left out
// where the record reads its line again with only sure hits of the set
// between.
std::vector<TexLine> kept_by_the_rules(const std::vector<TexLine>& lines, uint64_t sets, int ways) {
  const auto set_of = [&](TexLine l) { return tex_line_index(l) % sets; };
  std::vector<TexLine> first;
  std::map<uint64_t, TexLine> last;
  for (const TexLine l : lines) {
    const auto it = last.find(set_of(l));
    if (it != last.end() && it->second == l) continue;
    last[set_of(l)] = l;
    first.push_back(l);
  }
  if (ways == 0) return first;
  const size_t n = first.size();
  std::vector<bool> sure(n, false);
  for (size_t i = 0; i < n; ++i) {
    std::vector<TexLine> others;  // the set's other lines read since the line last was
    for (size_t j = i; j-- > 0;) {
      if (set_of(first[j]) != set_of(first[i])) continue;
      if (first[j] == first[i]) {
        sure[i] = int(others.size()) < ways;
        break;
      }
      if (std::find(others.begin(), others.end(), first[j]) == others.end()) others.push_back(first[j]);
    }
  }
  std::vector<TexLine> kept;
  for (size_t i = 0; i < n; ++i) {
    bool read_again = false;
    for (size_t j = i + 1; j < n && sure[i]; ++j) {
      if (set_of(first[j]) != set_of(first[i])) continue;
      if (first[j] == first[i]) {
        read_again = true;
        break;
      }
      if (!sure[j]) break;
    }
    if (!read_again) kept.push_back(first[i]);
  }
  return kept;
}

TEST(Trace, TextureLinesWithoutRepeatsAreWhatTheRulesSay) {
  // The derivation against the rules written out read by read, on 2,000
  // random records (re-reads of the read before, cycles among 2 to 10
  // lines of one set, which the LRU rule is for, and lines of any set),
  // with any policy and with LRU of 1 to 6, 8 and 16 ways: the same lines
  // kept, record by record. The derivation's moves in its set's stack are
  // written out up to four ways (Table 1's L1) and looped beyond; one that
  // kept a sure hit it may leave out would still replay right, so only
  // this finds it.
  constexpr uint64_t kSets = 8;
  FrameTrace t;
  Rng rng(7);
  test::add_random_records(
      t, rng, {.records = 2000, .sets = kSets, .spread = 64, .repeats_in_ten = 4, .widths = 9, .textures = 3, .any_lines = 100});
  // A record or two of one line read many times: the repeats the majority,
  // so that the list is kept whatever the ways.
  for (int r = 0; r < 2; ++r) {
    TileWork w;
    w.tex_begin = t.tex_lines.size();
    w.tex_count = 60000;
    for (uint32_t i = 0; i < w.tex_count; ++i) t.tex_lines.push_back(make_tex_line(0, 1));
    t.tiles.push_back(w);
  }
  uint64_t sure_left_out = 0, by_rule_one = 0;  // by_rule_one: the list's size with any policy (0 ways, first)
  for (const int ways : {0, 1, 2, 3, 4, 5, 6, 8, 16}) {
    SCOPED_TRACE(std::to_string(ways) + " ways");
    const auto kept = t.tex_lines_without_repeats(kSets, ways);
    ASSERT_NE(kept, nullptr);
    ASSERT_EQ(kept->begin.size(), t.tiles.size() + 1);
    for (size_t r = 0; r < t.tiles.size(); ++r) {
      const TileWork& w = t.tiles[r];
      const std::vector<TexLine> lines(t.tex_lines.begin() + std::ptrdiff_t(w.tex_begin),
                                       t.tex_lines.begin() + std::ptrdiff_t(w.tex_begin + w.tex_count));
      const std::vector<TexLine> derived(kept->lines.begin() + std::ptrdiff_t(kept->begin[r]),
                                         kept->lines.begin() + std::ptrdiff_t(kept->begin[r + 1]));
      ASSERT_EQ(derived, kept_by_the_rules(lines, kSets, ways)) << "record " << r;
    }
    if (ways == 0) by_rule_one = kept->lines.size();
    if (ways > 1) sure_left_out += by_rule_one - kept->lines.size();
  }
  EXPECT_GT(sure_left_out, 10000u);  // the LRU rule is exercised
}

}  // namespace
}  // namespace oovr
