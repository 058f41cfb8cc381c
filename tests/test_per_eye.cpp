// per-eye (schemes/impl/per_eye.cpp): each eye on its own half of the GPMs,
// draws broadcast, the eyes never composed together. The numbers below are
// worked out from the frame's trace by the scheme's definition.
#include <gtest/gtest.h>

#include "oovr/memory/category.h"
#include "oovr/scene/builtin.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& crowd() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("crowd", 96, 64, 3, 1);
  return *r;
}

SchemeResult per_eye(int gpms, const char* split = nullptr) {
  Config c;
  c.set("gpms", std::to_string(gpms));
  if (split) c.set("per_eye.split", split);
  const auto& r = crowd();
  return run_scheme("per-eye", r.scene, r.traces, c);
}

struct Totals {
  uint64_t draws = 0, vertices = 0, covered = 0;
};
Totals totals(const FrameTrace& f) {
  Totals t;
  t.draws = f.objects.size();
  for (const ObjectWork& o : f.objects) t.vertices += o.vertices;
  for (const TileWork& w : f.tiles) t.covered += w.covered;
  return t;
}

// Split by tiles: every GPM receives every draw and transforms it for its
// own eye (one GPM transforms it once per eye); nothing is composed.
TEST(PerEye, ByTilesEveryGpmTransformsEveryDrawForItsEye) {
  const FrameTrace& f = *crowd().traces[0];
  const Totals t = totals(f);
  ASSERT_GT(t.draws, 3u);
  for (int n : {1, 2, 4, 3}) {
    const SchemeResult r = per_eye(n);
    EXPECT_EQ(r.draws, (n == 1 ? 1 : uint64_t(n)) * t.draws) << n;
    EXPECT_EQ(r.vertices, (n == 1 ? 2 : uint64_t(n)) * t.vertices) << n;
    EXPECT_EQ(r.covered_fragments, t.covered) << n;
    EXPECT_EQ(r.inter_gpm_bytes[size_t(Category::composition)], 0u) << n;
  }
  // The baseline transforms each draw once for both eyes (SMP): per-eye
  // spends twice its vertex work on two GPMs, four times on four.
  Config four;
  EXPECT_EQ(run_scheme("baseline", crowd().scene, crowd().traces, four).vertices, t.vertices);
}

// Split by objects (4 GPMs): object o of the left eye renders on GPM o % 2,
// of the right eye on 2 + o % 2, each sent to those two GPMs only and
// transformed once per eye; the
// halves' second GPMs send the lines they wrote to their half's first,
// whose ROPs compose them, and the eyes send each other nothing.
TEST(PerEye, ByObjectsEachHalfComposesOnItsFirstGpm) {
  const FrameTrace& f = *crowd().traces[0];
  const Totals t = totals(f);
  const SchemeResult r = per_eye(4, "objects");
  EXPECT_EQ(r.draws, 2 * t.draws);
  EXPECT_EQ(r.vertices, 2 * t.vertices);
  EXPECT_EQ(r.covered_fragments, t.covered);
  uint64_t lines = 0;  // colour lines written by a half's second GPM (odd objects)
  for (const TileWork& w : f.tiles)
    if (w.object % 2 == 1) lines += uint64_t(__builtin_popcount(w.colour_write_mask));
  ASSERT_GT(lines, 0u);
  EXPECT_EQ(r.inter_gpm_bytes[size_t(Category::composition)], lines * f.line_bytes);
  // Two GPMs: a half each, nothing to compose.
  EXPECT_EQ(per_eye(2, "objects").inter_gpm_bytes[size_t(Category::composition)], 0u);
}

TEST(PerEye, ABadSplitIsRefusedNamingTheKey) {
  EXPECT_NE(test::message_of([] { (void)per_eye(4, "strips"); }).find("per_eye.split"), std::string::npos);
}

}  // namespace
}  // namespace oovr
