// OO-VR's mechanisms on hand-made cases: the texture sharing level
// (Equation 1), batching, the predictor (Equation 3), the distribution
// engine's choice and its storage (Section 5.4).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <list>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/rng.h"
#include "oovr/framework/distribution.h"
#include "oovr/framework/middleware.h"
#include "oovr/framework/oo_application.h"
#include "oovr/framework/oo_spec.h"
#include "oovr/framework/runtime.h"
#include "oovr/scene/builtin.h"

namespace oovr {
namespace {

TEST(Framework, TextureSharingLevelFollowsEquation1) {
  // Root: A (300 B) and B (100 B): P_r(A) = 0.75, P_r(B) = 0.25.
  const TextureSet root = {{0, 300}, {1, 100}};
  // Next: A (100 B) and C (100 B): P_n(A) = 0.5. Shared: A only.
  // TSL = 0.75 * 0.5 / 0.75 = 0.5.
  EXPECT_DOUBLE_EQ(texture_sharing_level(root, {{0, 100}, {2, 100}}), 0.5);
  // Next: B only (P_n(B) = 1): TSL = 0.25 * 1 / 0.25 = 1.
  EXPECT_DOUBLE_EQ(texture_sharing_level(root, {{1, 50}}), 1.0);
  // Next: A and B (P_n = 0.2 and 0.8): (0.75*0.2 + 0.25*0.8) / (0.75 + 0.25) = 0.35.
  EXPECT_NEAR(texture_sharing_level(root, {{0, 20}, {1, 80}}), 0.35, 1e-12);
  EXPECT_EQ(texture_sharing_level(root, {{7, 10}}), 0.0) << "nothing shared";
  EXPECT_EQ(texture_sharing_level(root, {}), 0.0);
  EXPECT_EQ(texture_sharing_level({}, root), 0.0);
}

// A scene of draws with the given triangle counts, textures and
// dependencies; texture t is (8 << t) texels square, one level: 256 B,
// 1 KB, 4 KB, 16 KB.
struct Spec {
  uint64_t triangles;
  std::vector<uint32_t> textures;
  std::vector<uint32_t> after;
};
OOApplication app_of(const std::vector<Spec>& objects, int textures = 4) {
  Scene s;
  s.name = "hand-made";
  for (int t = 0; t < textures; ++t) {
    Texture tex;
    tex.name = "t" + std::to_string(t);
    const int w = 8 << t;
    tex.levels.push_back({w, w, std::vector<uint8_t>(size_t(w) * size_t(w) * 4, 0)});
    s.textures.push_back(tex);
  }
  OOApplication app;
  for (size_t i = 0; i < objects.size(); ++i) {
    Mesh m;
    m.vertices.resize(3);
    for (uint64_t k = 0; k < objects[i].triangles; ++k) m.indices.insert(m.indices.end(), {0, 1, 2});
    s.meshes.push_back(m);
    Material mat = Material::textured("m", objects[i].textures.size() > 0 ? int(objects[i].textures[0]) : -1,
                                      objects[i].textures.size() > 1 ? int(objects[i].textures[1]) : -1);
    s.materials.push_back(mat);
    Object o;
    o.mesh = int(i);
    o.material = int(i);
    s.objects.push_back(o);
    app.add_object_auto(s, uint32_t(i), {0, 0, 320, 480});
    for (uint32_t p : objects[i].after) app.add_dependency(uint32_t(i), p);
  }
  return app;
}

std::vector<std::vector<uint32_t>> members(const std::vector<Batch>& b) {
  std::vector<std::vector<uint32_t>> r;
  for (const auto& x : b) r.push_back(x.objects);
  return r;
}

TEST(Framework, TheAutoModelShiftsTheViewportAlongX) {
  const OOApplication app = app_of({{1, {0}, {}}});
  const OOObject& o = app.objects()[0];
  EXPECT_EQ(o.viewport[0].x, 0);
  EXPECT_EQ(o.viewport[1].x, 320);
  EXPECT_EQ(o.viewport[1].width, 320);
  EXPECT_EQ(o.viewport[1].height, 480);
  EXPECT_THROW(OOApplication().add_dependency(0, 0), Error);
}

TEST(Framework, BatchesGroupObjectsThatShareTextures) {
  // 0, 2 and 3 use texture 0; 1 uses texture 1; 4 uses 1 (1 KB) and 0 (256 B).
  const auto b = make_batches(app_of({{10, {0}, {}}, {10, {1}, {}}, {10, {0}, {}}, {10, {0}, {}}, {10, {1, 0}, {}}}), {});
  // Root 0 takes 2 and 3 (TSL 1) but not 4 (texture 0 is 20% of its bytes:
  // TSL 0.2); root 1 takes 4 (texture 1 is 80% of 4's bytes: TSL 0.8).
  EXPECT_EQ(members(b), (std::vector<std::vector<uint32_t>>{{0, 2, 3}, {1, 4}}));
  EXPECT_EQ(b[0].triangles, 30u);
  EXPECT_EQ(b[0].textures.size(), 1u);
  EXPECT_EQ(b[1].textures.size(), 2u) << "the union of its objects' textures";
}

TEST(Framework, ABatchClosesOnceItHoldsMoreThanTheCap) {
  // Five objects of 2000 triangles, all on one texture: 2000, 4000, then
  // 6000 > 4096 closes the batch.
  std::vector<Spec> objects(5, Spec{2000, {0}, {}});
  const auto b = make_batches(app_of(objects), {0.5, 4096});
  EXPECT_EQ(members(b), (std::vector<std::vector<uint32_t>>{{0, 1, 2}, {3, 4}}));
  // A lower threshold and cap are configuration.
  EXPECT_EQ(make_batches(app_of(objects), {0.5, 1000}).size(), 5u);
}

TEST(Framework, DependentObjectsJoinTheBatchInOrderWhateverTheCap) {
  // 1 (texture 1) must follow 0 (texture 0); 3 must follow 1. The batch of
  // 0 would close at the cap, but 1 and then 3 join it, in order.
  const auto b = make_batches(app_of({{5000, {0}, {}}, {100, {1}, {0}}, {100, {0}, {}}, {100, {2}, {1}}}), {0.5, 4096});
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].objects, (std::vector<uint32_t>{0, 1, 3}));
  EXPECT_EQ(b[1].objects, (std::vector<uint32_t>{2}));
  // An object that follows one still waiting is not taken by an unrelated
  // root ahead of it: 2 shares 0's texture but must follow 1.
  const auto c = make_batches(app_of({{10, {0}, {}}, {10, {1}, {}}, {10, {0}, {1}}}), {});
  EXPECT_EQ(members(c), (std::vector<std::vector<uint32_t>>{{0}, {1, 2}}));
  // Every object in exactly one batch, and every batch in order.
  std::vector<int> times(4, 0);
  for (const auto& x : b) {
    EXPECT_TRUE(std::is_sorted(x.objects.begin(), x.objects.end()));
    for (uint32_t o : x.objects) ++times[o];
  }
  EXPECT_EQ(times, (std::vector<int>{1, 1, 1, 1}));
}

// Section 5.1's batching as first written, the queue a list that each taken
// object is removed from: the reference make_batches() must agree with.
std::vector<Batch> batches_by_list(const OOApplication& app, const MiddlewareSettings& s) {
  const auto& objects = app.objects();
  std::vector<bool> waiting(objects.size(), true);
  std::list<uint32_t> queue;
  for (uint32_t i = 0; i < objects.size(); ++i) queue.push_back(i);
  std::vector<Batch> batches;
  while (!queue.empty()) {
    Batch b;
    std::vector<bool> member(objects.size(), false);
    uint64_t cap = s.triangle_cap;
    const auto take = [&](uint32_t o) {
      member[o] = true;
      waiting[o] = false;
      queue.remove(o);
      b.objects.push_back(o);
      b.triangles += objects[o].triangles;
      b.vertices += objects[o].vertices;
      for (const auto& x : objects[o].textures)
        if (std::none_of(b.textures.begin(), b.textures.end(), [&](const auto& y) { return y.first == x.first; }))
          b.textures.push_back(x);
    };
    const std::function<void(uint32_t)> take_with_predecessors = [&](uint32_t o) {
      for (uint32_t p : objects[o].after)
        if (waiting[p]) take_with_predecessors(p);
      if (!waiting[o]) return;
      cap += objects[o].triangles;
      take(o);
    };
    const auto depends_on_member = [&](uint32_t o) {
      return std::any_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return member[p]; });
    };
    const auto independent = [&](uint32_t o) {
      return std::none_of(objects[o].after.begin(), objects[o].after.end(), [&](uint32_t p) { return waiting[p]; });
    };
    take(queue.front());
    for (auto it = queue.begin(); it != queue.end() && b.triangles <= cap;) {
      const uint32_t o = *it++;
      if (!waiting[o]) continue;
      if (depends_on_member(o)) {
        take_with_predecessors(o);
        continue;
      }
      if (!independent(o)) continue;
      if (texture_sharing_level(b.textures, objects[o].textures) > s.tsl_threshold) take(o);
    }
    for (bool again = true; again;) {
      again = false;
      for (uint32_t o : std::vector<uint32_t>(queue.begin(), queue.end()))
        if (waiting[o] && depends_on_member(o)) {
          take_with_predecessors(o);
          again = true;
        }
    }
    std::sort(b.objects.begin(), b.objects.end());
    batches.push_back(std::move(b));
  }
  return batches;
}

TEST(Framework, BatchesAreTheListFormulationsOnRandomApplications) {
  // 200 applications of 1 to 60 objects: 1 to 3,000 triangles, one or two
  // of four textures, each object following up to three earlier ones a
  // third of the time; caps and thresholds from tight to loose. The same
  // batches, members, counts and textures.
  Rng rng(31);
  size_t batches = 0, several = 0;
  for (int a = 0; a < 200; ++a) {
    std::vector<Spec> objects(1 + rng.below(60));
    for (size_t i = 0; i < objects.size(); ++i) {
      objects[i].triangles = 1 + rng.below(3000);
      objects[i].textures.push_back(rng.below(4));
      if (rng.below(2)) objects[i].textures.push_back(rng.below(4));
      if (i > 0 && rng.below(3) == 0)
        for (uint32_t k = 0, m = 1 + rng.below(3); k < m; ++k) objects[i].after.push_back(rng.below(uint32_t(i)));
    }
    const OOApplication app = app_of(objects);
    const MiddlewareSettings s{0.1 * double(rng.below(10)), uint64_t(500) << rng.below(5)};
    const auto got = make_batches(app, s), want = batches_by_list(app, s);
    ASSERT_EQ(got.size(), want.size()) << "application " << a;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].objects, want[k].objects) << "application " << a << ", batch " << k;
      EXPECT_EQ(got[k].triangles, want[k].triangles);
      EXPECT_EQ(got[k].vertices, want[k].vertices);
      EXPECT_EQ(got[k].textures, want[k].textures);
      several += got[k].objects.size() > 1;
    }
    batches += got.size();
  }
  // Both kinds of batch were made: objects alone and objects together.
  EXPECT_GT(several, 200u);
  EXPECT_GT(batches - several, 200u);
}

TEST(Framework, TheCourtyardBatchesItsPillarsAndKeepsItsDecalsWithTheirWalls) {
  const Scene s = BuiltinScenes::find("courtyard")->make();
  const auto b = make_batches(make_application(s, 1280, 1024), {});
  std::vector<int> batch_of(s.objects.size(), -1);
  for (size_t k = 0; k < b.size(); ++k)
    for (uint32_t o : b[k].objects) {
      EXPECT_EQ(batch_of[o], -1) << "object in two batches";
      batch_of[o] = int(k);
    }
  for (int x : batch_of) EXPECT_GE(x, 0) << "object in no batch";
  for (uint32_t o = 0; o < s.objects.size(); ++o)
    for (uint32_t p : s.objects[o].after) EXPECT_EQ(batch_of[o], batch_of[p]) << s.objects[o].name;
  EXPECT_LT(b.size(), s.objects.size()) << "objects sharing textures batch together";
}

TEST(Framework, ThePredictorRecoversKnownRates) {
  // Batches timed with c0 = 2 ns per triangle and c1 = 1 ns per vertex plus
  // c2 = 0.25 ns per pixel (made consistent by choosing the vertex counts).
  std::vector<BatchSample> s;
  for (int k = 1; k <= 8; ++k) {
    const double tri = 1000.0 * k, pixels = 4000.0 * k + 500.0 * (k % 3);
    const double seconds = 2e-9 * tri;
    const double vertices = (seconds - 0.25e-9 * pixels) / 1e-9;
    s.push_back({tri, vertices, pixels, seconds});
  }
  const Rates r = Rates::fit(s);
  EXPECT_NEAR(r.c0, 2e-9, 1e-18);
  EXPECT_NEAR(r.c1, 1e-9, 1e-15);
  EXPECT_NEAR(r.c2, 0.25e-9, 1e-15);
  EXPECT_THROW(Rates::fit(std::vector<BatchSample>{}), Error);
}

TEST(Framework, TheEnginePicksTheGpmPredictedFreeFirst) {
  DistributionEngine e(3, Rates{1e-9, 1e-9, 0});
  EXPECT_EQ(e.earliest_free(), 0) << "all free: the lowest id";
  e.assign(0, 0, 1000);  // GPM 0: 1000 ns to do
  e.assign(1, 1, 3000);  // GPM 1: 3000 ns
  e.assign(2, 2, 2000);  // GPM 2: 2000 ns
  EXPECT_EQ(e.earliest_free(), 0);
  // GPM 1 has done 2500 vertices' worth: 500 ns left, less than GPM 0's.
  e.set_elapsed(1, 2500, 0);
  EXPECT_DOUBLE_EQ(e.remaining(1), 500e-9);
  EXPECT_EQ(e.earliest_free(), 1);
  // Done early: never negative; a GPM holding nothing wins the tie.
  e.set_elapsed(1, 9000, 0);
  EXPECT_EQ(e.remaining(1), 0.0);
  e.finish(2);
  EXPECT_EQ(e.remaining(2), 0.0);
  EXPECT_EQ(e.earliest_free(), 2);
}

TEST(Framework, TheEngineWeighsExtraCostsAgainstPredictedFreeTimes) {
  DistributionEngine e(2, Rates{1e-9, 1e-9, 0});
  e.assign(0, 0, 1000);  // GPM 0 free in 1000 ns
  e.assign(1, 1, 1500);  // GPM 1 in 1500 ns
  const std::vector<double> none;
  EXPECT_EQ(e.cheapest(none), 0);
  // 1000 + 800 > 1500 + 0: the batch waits for GPM 1.
  EXPECT_EQ(e.cheapest(std::vector<double>{800e-9, 0}), 1);
  // 1000 + 400 < 1500: GPM 0 still.
  EXPECT_EQ(e.cheapest(std::vector<double>{400e-9, 0}), 0);
  // An equal sum: the GPM holding fewer batches, then the lower id.
  EXPECT_EQ(e.cheapest(std::vector<double>{500e-9, 0}), 0);
  EXPECT_THROW((void)e.cheapest(std::vector<double>{0, 0, 0}), Error);
}

namespace {

// Records where the runtime sends each batch: with pre-allocation on, the
// pre-allocation unit of the batch's GPM is asked first, in assignment
// order. Time stands still, so every prediction is the engine's own.
class Recorder final : public RuntimeExecutor {
 public:
  std::vector<std::pair<int, std::vector<uint32_t>>> copies;
  double now() const override { return 0; }
  double progress(int) const override { return 0; }
  int preallocate(int gpm, const std::vector<uint32_t>& objects, bool geometry, int) override {
    if (geometry) copies.push_back({gpm, objects});
    return -1;
  }
  void start_batch(int, const std::vector<uint32_t>&) override {}
  int geometry(int, uint32_t, int) override { return m_unit++; }
  int chunk(int, uint32_t, std::span<const TileWork* const>, int, int, int, int) override { return m_unit++; }

 private:
  int m_unit = 0;
};

// The GPM each of three one-object batches (1000, 2000 and 1000 triangles)
// goes to on 2 GPMs, the engine's rates given: 1 ns a triangle.
std::vector<int> placements(double affinity, std::vector<std::vector<double>> link_seconds) {
  OOSpec spec;
  spec.affinity = affinity;
  spec.split = false;
  std::vector<Batch> batches;
  for (uint32_t o = 0; o < 3; ++o) batches.push_back({{o}, o == 1 ? 2000u : 1000u, 1000, {}});
  const std::vector<std::vector<const TileWork*>> records(3);
  const std::vector<uint64_t> vertices(3, 1000);
  Recorder exec;
  OORuntime rt(spec, 2, batches, records, vertices, exec, Rates{1e-9, 1e-9, 0}, std::move(link_seconds));
  rt.start();
  std::vector<int> gpm(3, -1);
  for (const auto& [g, objects] : exec.copies) gpm[objects.at(0)] = g;
  return gpm;
}

}  // namespace

TEST(Framework, ScreenAffinityTradesPredictedWaitForLinkTime) {
  // Object 0 costs 2000 ns of links on GPM 0 and none on 1, object 1 500 ns
  // on GPM 1, object 2 2000 ns on GPM 1.
  const std::vector<std::vector<double>> cost = {{2000e-9, 0}, {0, 500e-9}, {0, 2000e-9}};
  // Off (the paper's engine): batch 0 to GPM 0 (both free: the lower id),
  // batch 1 to the free GPM 1, batch 2 to GPM 0 (free in 1000 ns against
  // 2000).
  EXPECT_EQ(placements(0, cost), (std::vector<int>{0, 1, 0}));
  // Weight 1: batch 0 to GPM 1 (0 + 0 against 0 + 2000); batch 1 to GPM 0
  // (0 + 0 against 1000 + 500); batch 2 to GPM 0 (2000 + 0 against
  // 1000 + 2000).
  EXPECT_EQ(placements(1, cost), (std::vector<int>{1, 0, 0}));
  // Weight 0.25: batch 2 now waits less on GPM 1 (1000 + 500 against 2000).
  EXPECT_EQ(placements(0.25, cost), (std::vector<int>{1, 0, 1}));
  // Unknown objects cost nothing anywhere: the paper's choices.
  EXPECT_EQ(placements(1, {{}, {}, {}}), (std::vector<int>{0, 1, 0}));
  // Costs that do not fit the frame or the machine are refused.
  EXPECT_THROW(placements(1, {{0, 0}}), Error);
  EXPECT_THROW(placements(1, {{0, 0, 0}, {}, {}}), Error);
}

TEST(Framework, EngineStorageIs960BitsForThePapersMachine) {
  EXPECT_EQ(engine_storage(4, 4).total(), 960);
  EXPECT_EQ(engine_storage(8, 4).total(), 8 * 128 + 64 + 8 * 96);
}

TEST(Framework, SpecReadsItsKeysAndRefusesBadValues) {
  Config c;
  c.set("oo.tsl_threshold=0.3");
  c.set("oo.composition=root");
  const OOSpec s = OOSpec::from_config(c, OOSpec{});
  EXPECT_DOUBLE_EQ(s.tsl_threshold, 0.3);
  EXPECT_FALSE(s.distributed_composition);
  EXPECT_TRUE(s.prealloc) << "the scheme's default";
  // Declared by OO-VR's own configuration section: checked whatever runs.
  Config bad;
  bad.set("oo.composition=everywhere");
  EXPECT_THROW(check_config(bad), Error);
  Config bad2;
  bad2.set("oo.batch_triangles=0");
  EXPECT_THROW(check_config(bad2), Error);
  Config given;
  given.set("oo.split=false");
  EXPECT_NO_THROW(check_config(given));
  EXPECT_EQ(Config{}.resolved().count("oo.split"), 0u);
  Config none;
  check_config(none);
  EXPECT_EQ(none.resolved().count("oo.split"), 0u) << "a switch's default is the scheme's, not the machine's";
  EXPECT_EQ(none.resolved().count("oo.batch_queue"), 1u);
}

}  // namespace
}  // namespace oovr
