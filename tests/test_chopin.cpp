// chopin (schemes/impl/chopin.cpp): every draw whole to one GPM, chosen by
// fewest outstanding triangles in an opaque group and by runs of equal
// triangles in a blended one; groups cut where blending switches. The
// numbers below are worked out from the frame's trace by the scheme's
// definition (the composition's bytes: test_composition.cpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "oovr/scene/builtin.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

// The crowd with draws 5, 6 and 10 blended (alpha over): groups [0, 5)
// opaque, [5, 7) blended, [7, 10) opaque, [10, 11) blended, [11, ...)
// opaque.
const test::RenderedFrames& blended_crowd() {
  static const std::unique_ptr<test::RenderedFrames> r = [] {
    auto out = std::make_unique<test::RenderedFrames>(test::RenderedFrames{BuiltinScenes::find("crowd")->make(), {}, {}});
    Scene& s = out->scene;
    for (uint32_t o : {5u, 6u, 10u}) {
      Material m = s.materials[size_t(s.objects[o].material)];
      m.name += "-over";
      m.passes[size_t(s.objects[o].pass)].src = BlendFactor::src_alpha;
      m.passes[size_t(s.objects[o].pass)].dst = BlendFactor::one_minus_src_alpha;
      s.materials.push_back(m);
      s.objects[o].material = int(s.materials.size() - 1);
    }
    StereoRig rig;
    rig.eye_width = 96;
    rig.eye_height = 64;
    out->out.push_back(render_frame(s, make_stereo_view(s.camera, 3, rig), {}, 3));
    out->traces.push_back(&out->out.back().trace);
    return out;
  }();
  return *r;
}

SchemeResult chopin(int gpms, std::vector<std::string> set = {}) {
  Config c;
  c.set("gpms", std::to_string(gpms));
  for (const std::string& kv : set) c.set(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1));
  const auto& r = blended_crowd();
  return run_scheme("chopin", r.scene, r.traces, c);
}

// The GPM that shaded each draw (-1: it covered nothing).
std::vector<int> gpm_of_draws(const FrameTrace& f, const SchemeResult& r) {
  std::vector<int> g(f.objects.size(), -1);
  for (const TileWork& w : f.tiles) g[w.object] = r.owner_of(w.object, uint32_t(w.tile_y) * uint32_t(f.tiles_x) + w.tile_x);
  return g;
}

TEST(Chopin, EveryDrawGoesWholeToOneGpm) {
  const FrameTrace& f = *blended_crowd().traces[0];
  ASSERT_GT(f.objects.size(), 12u);
  uint64_t vertices = 0, covered = 0;
  for (const ObjectWork& o : f.objects) vertices += o.vertices;
  for (const TileWork& w : f.tiles) covered += w.covered;
  for (int n : {1, 2, 4}) {
    const SchemeResult r = chopin(n);
    EXPECT_EQ(r.draws, f.objects.size()) << n;
    EXPECT_EQ(r.vertices, vertices) << n << ": once, both eyes (SMP)";
    EXPECT_EQ(r.covered_fragments, covered) << n;
    // Each draw's records all on one GPM.
    for (const TileWork& w : f.tiles)
      EXPECT_EQ(r.owner_of(w.object, uint32_t(w.tile_y) * uint32_t(f.tiles_x) + w.tile_x), gpm_of_draws(f, r)[w.object]);
    EXPECT_EQ(r.stats.at("chopin", "groups"), 5) << n;
    EXPECT_EQ(r.stats.at("chopin", "groups.blended"), 2) << n;
  }
  EXPECT_EQ(chopin(4, {"chopin.groups=frame"}).stats.at("chopin", "groups"), 1);
}

// The frame's draws fit the front ends' window (64 draws each), so the
// first group's draws are all given out at once, before any has started:
// each to the GPM with the fewest triangles scheduled, ties to the first
// GPM after the one chosen last. A blended group's draw goes to the run its
// middle triangle falls in: run floor((2 x before + t) x N / (2 x total)).
TEST(Chopin, DrawsGoWhereTheSchedulersDefinitionSays) {
  const FrameTrace& f = *blended_crowd().traces[0];
  for (int n : {2, 4}) {
    const std::vector<int> got = gpm_of_draws(f, chopin(n));
    for (uint32_t o : {5u, 6u, 10u}) ASSERT_GE(got[o], 0) << "draw " << o << " covers something";
    ASSERT_GE(std::count_if(got.begin(), got.begin() + 5, [](int g) { return g >= 0; }), 3);
    std::vector<uint64_t> load(size_t(n), 0);
    int last = -1;
    const auto opaque = [&](uint32_t first, uint32_t end) {
      for (uint32_t o = first; o < end; ++o) {
        int best = -1;
        for (int k = 1; k <= n; ++k) {
          const int g = (last + k + n) % n;
          if (best < 0 || load[size_t(g)] < load[size_t(best)]) best = g;
        }
        load[size_t(best)] += f.objects[o].triangles;
        last = best;
        if (got[o] >= 0) {
          EXPECT_EQ(got[o], best) << "draw " << o << " at " << n << " GPMs";
        }
      }
    };
    opaque(0, 5);
    // The third group starts once the second is composed: every draw
    // before has ended, nothing is outstanding, the ties rotate on.
    std::fill(load.begin(), load.end(), 0);
    opaque(7, 10);
    ASSERT_GE(got[7], 0);
    const uint64_t total = uint64_t(f.objects[5].triangles) + f.objects[6].triangles;
    const int run5 = int(uint64_t(f.objects[5].triangles) * uint64_t(n) / (2 * total));
    const int run6 =
        std::min(n - 1, int((2 * uint64_t(f.objects[5].triangles) + f.objects[6].triangles) * uint64_t(n) / (2 * total)));
    EXPECT_EQ(got[5], run5) << n;
    EXPECT_EQ(got[6], run6) << n;
    EXPECT_EQ(got[10], n / 2) << n << ": one draw, the middle run";
  }
  // Round-robin: the first group's draws in turn from GPM 0.
  const std::vector<int> rr = gpm_of_draws(f, chopin(4, {"chopin.scheduler=round-robin"}));
  for (uint32_t o = 0; o < 5; ++o) {
    if (rr[o] >= 0) {
      EXPECT_EQ(rr[o], int(o % 4)) << o;
    }
  }
}

// One group for the frame is a bound: the blended frame's five groups each
// end with their composition's rounds before the next begins (the barrier
// itself is checked by the draws of the third group above).
TEST(Chopin, OneGroupForTheFrameIsABound) {
  const SchemeResult groups = chopin(4), one = chopin(4, {"chopin.groups=frame"});
  EXPECT_GT(groups.frame_latency_s, one.frame_latency_s);
}

TEST(Chopin, BadSettingsAreRefusedNamingTheKey) {
  EXPECT_NE(test::message_of([] { (void)chopin(4, {"chopin.scheduler=fastest"}); }).find("chopin.scheduler"), std::string::npos);
  EXPECT_NE(test::message_of([] { (void)chopin(4, {"chopin.groups=draw"}); }).find("chopin.groups"), std::string::npos);
}

}  // namespace
}  // namespace oovr
