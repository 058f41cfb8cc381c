// gpupd (schemes/impl/gpupd.cpp): cooperative projection, primitive IDs
// exchanged in API order, sort-first rendering in vertical strips. The
// numbers below are worked out from the frame's trace by the scheme's
// definition.
#include <gtest/gtest.h>

#include <cmath>

#include "oovr/memory/category.h"
#include "oovr/scene/builtin.h"
#include "oovr/schemes/i_scheme.h"
#include "oovr/schemes/sort_first.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& crowd() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("crowd", 96, 64, 3, 1);
  return *r;
}

SchemeResult gpupd(int gpms, std::initializer_list<const char*> settings = {}) {
  Config c;
  c.set("gpms", std::to_string(gpms));
  for (const char* s : settings) c.set(s);
  return run_scheme("gpupd", crowd().scene, crowd().traces, c);
}

// Each draw's set-up triangles in each GPM's strip (both eyes), as the
// trace's tile records count them.
std::vector<std::vector<uint64_t>> primitives(const FrameTrace& f, int n) {
  std::vector<std::vector<uint64_t>> p(f.objects.size(), std::vector<uint64_t>(size_t(n), 0));
  for (const TileWork& w : f.tiles) p[w.object][size_t(vertical_strip_owner(w.tile_x, f.tiles_x, n))] += w.triangles;
  return p;
}

// Draw by draw (no batching): every GPM receives every draw and projects
// its 1/N of the draw's vertices; each GPM shades the share of a draw's
// vertices its strip's primitives make up; every primitive ID (4 bytes)
// a GPM projected for another's strip crosses the links once.
TEST(Gpupd, DrawByDrawEveryFigureIsTheDefinitions) {
  const FrameTrace& f = *crowd().traces[0];
  const auto& meshes = crowd().scene.meshes;
  const auto& objects = crowd().scene.draws(f.frame);
  for (int n : {2, 4}) {
    const auto p = primitives(f, n);
    uint64_t vertices = 0, bytes = 0, covered = 0;
    for (uint32_t o = 0; o < f.objects.size(); ++o) {
      const double v = double(meshes[size_t(objects[o].mesh)].vertices.size());
      for (int g = 0; g < n; ++g) {
        vertices += uint64_t(std::llround((double(g + 1) / n - double(g) / n) * v));  // projection
        bool has_tiles = false;
        for (const TileWork& w : f.tiles)
          has_tiles = has_tiles || (w.object == o && vertical_strip_owner(w.tile_x, f.tiles_x, n) == g);
        if (has_tiles)
          vertices += uint64_t(std::llround(std::min(1.0, double(p[o][size_t(g)]) / std::max(1u, f.objects[o].triangles)) * v));
        bytes += uint64_t(n - 1) * uint64_t(std::llround(double(p[o][size_t(g)]) / n)) * 4;
      }
    }
    for (const TileWork& w : f.tiles) covered += w.covered;
    const SchemeResult r = gpupd(n, {"gpupd.batching=false"});
    EXPECT_EQ(r.draws, uint64_t(n) * f.objects.size()) << n;
    EXPECT_EQ(r.vertices, vertices) << n;
    EXPECT_EQ(r.covered_fragments, covered) << n;
    EXPECT_GT(bytes, 0u);
    EXPECT_EQ(r.inter_gpm_bytes[size_t(Category::command)], bytes) << n;
    EXPECT_EQ(r.inter_gpm_bytes[size_t(Category::composition)], 0u) << n;
  }
}

// One batch of every draw: the IDs of the whole batch go at once, each
// sender's count rounded once.
TEST(Gpupd, ABatchSendsItsIdsTogether) {
  const FrameTrace& f = *crowd().traces[0];
  const int n = 4;
  const auto p = primitives(f, n);
  uint64_t bytes = 0;
  for (int g = 0; g < n; ++g) {
    double ids = 0;
    for (uint32_t o = 0; o < f.objects.size(); ++o) ids += double(p[o][size_t(g)]) / n;
    bytes += uint64_t(n - 1) * uint64_t(std::llround(ids)) * 4;
  }
  const SchemeResult r = gpupd(n, {"gpupd.batch_draws=100000", "gpupd.batch_primitives=1000000000"});
  EXPECT_EQ(r.inter_gpm_bytes[size_t(Category::command)], bytes);
}

// Runahead lets a GPM project the next batch while the exchange of this
// one is under way: never slower than projecting after rendering.
TEST(Gpupd, RunaheadNeverSlows) {
  const SchemeResult ahead = gpupd(4, {"gpupd.batching=false"});
  const SchemeResult after = gpupd(4, {"gpupd.batching=false", "gpupd.runahead=false"});
  EXPECT_LE(ahead.frame_latency_s, after.frame_latency_s);
  EXPECT_EQ(ahead.vertices, after.vertices);
  EXPECT_NE(test::message_of([] { (void)gpupd(4, {"gpupd.projection_cost=2"}); }).find("gpupd.projection_cost"),
            std::string::npos);
}

}  // namespace
}  // namespace oovr
