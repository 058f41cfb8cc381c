// The frame's conservation laws, checked after every run of every scheme
// (schemes/conservation.h): each registered scheme obeys them, and a scheme
// that breaks one (no work, work twice, work without its draw, pixels never
// composed or composed twice) is an Error naming the scheme, the law and
// where, not a result.
#include <gtest/gtest.h>

#include <functional>
#include <memory>

#include "oovr/core/error.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/scene/builtin.h"
#include "oovr/schemes/composition.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/i_scheme.h"
#include "oovr/schemes/sort_first.h"
#include "test_util.h"

namespace oovr {
namespace {

using Frames = test::RenderedFrames;

// Four frames of a built-in scene at 160x96, rendered once per scene.
const Frames& frames(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Frames>> cache;
  std::unique_ptr<Frames>& f = cache[name];
  if (!f) f = test::render_builtin(name, 80, 96, 10, 4);
  return *f;
}

// A scheme made of a function, as a user's file or a Python class would be.
class Custom final : public Scheme {
 public:
  explicit Custom(std::function<SchemeResult(const SchemeInput&)> run) : m_run(std::move(run)) {}
  SchemeResult run(const SchemeInput& in) const override { return m_run(in); }

 private:
  std::function<SchemeResult(const SchemeInput&)> m_run;
};

std::string run_custom(const std::string& name, std::function<SchemeResult(const SchemeInput&)> f) {
  const Frames& fr = frames("courtyard");
  return test::message_of([&] {
    (void)run_scheme({name, std::make_shared<Custom>(std::move(f))}, fr.scene, {fr.traces[0]}, Config{});
  });
}

// Object-level SFR on one GPM, object by object, with hooks to break it.
struct Breaks {
  bool command = true;          // the GPM's front end receives each draw
  int draw_every = 1;           // a new draw every n objects (n > 1: objects share a draw)
  int times = 1;                // each object's records rasterised this often
  bool private_buffer = false;  // written into GPM 0's own buffer (framebuffer 1), not the final one
  int compositions = 0;         // then composed this often
  int declared_repeats = 0;     // the scheme declares it repeats records (0: says nothing)
};

SchemeResult simple(const SchemeInput& in, const Breaks& b) {
  FrameSim sim(in, 2);
  if (b.declared_repeats) sim.declare_repeats(b.declared_repeats);
  const FrameTrace& f = sim.frame();
  const std::vector<ObjectRecords> objects = records_by_object(f, sim.scene().objects.size());
  for (uint32_t o = 0; o < objects.size(); ++o) {
    if (b.command && o % uint32_t(b.draw_every) == 0) sim.command(0);
    const int geo = sim.geometry(0, o, 1, uint64_t(f.objects[o].setup[0]) + f.objects[o].setup[1]);
    for (int e = 0; e < 2; ++e) {
      if (objects[o].eye[e].empty()) continue;
      for (int k = 0; k < b.times; ++k) (void)sim.tiles(0, objects[o].eye[e], b.private_buffer ? 1 : 0, f, {geo});
      for (int k = 0; k < b.compositions; ++k) sim.compose(0, objects[o].eye[e], 1, {});
    }
    sim.end_draw(0);
  }
  return sim.finish("simple");
}

TEST(Conservation, EveryRegisteredSchemeKeepsTheLaws) {
  for (const char* scene : {"courtyard", "crowd"}) {
    const Frames& fr = frames(scene);
    for (const auto& name : Schemes::names())
      for (const char* gpms : {"gpms=2", "gpms=4"}) {
        Config c;
        c.set(gpms);
        SchemeResult r;
        const std::string error = test::message_of([&] { r = run_scheme_window(name, fr.scene, fr.traces, c, 4); });
        EXPECT_EQ(error, "<no error>") << name << " on " << scene << ", " << gpms;
        EXPECT_TRUE(r.laws_checked) << name;
      }
  }
}

TEST(Conservation, TheSimpleSchemeKeepsThem) {
  EXPECT_EQ(run_custom("simple", [](const SchemeInput& in) { return simple(in, {}); }), "<no error>");
  Breaks composed;
  composed.private_buffer = true;
  composed.compositions = 1;
  EXPECT_EQ(run_custom("simple", [&](const SchemeInput& in) { return simple(in, composed); }), "<no error>");
}

TEST(Conservation, ASchemeThatDoesNoWorkIsAnError) {
  const std::string m = run_custom("idle", [](const SchemeInput& in) { return FrameSim(in).finish("idle"); });
  EXPECT_NE(m.find("scheme 'idle' breaks a conservation law (every covered fragment rasterised once per eye): frame 0 of the "
                   "run: object "),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("was never rasterised (and "), std::string::npos) << m;
}

TEST(Conservation, WorkDoneTwiceIsAnErrorUnlessDeclared) {
  Breaks twice;
  twice.times = 2;
  const std::string m = run_custom("twice", [&](const SchemeInput& in) { return simple(in, twice); });
  EXPECT_NE(m.find("(every covered fragment rasterised once per eye)"), std::string::npos) << m;
  EXPECT_NE(m.find("was rasterised twice"), std::string::npos) << m;
  twice.declared_repeats = 2;
  EXPECT_EQ(run_custom("twice", [&](const SchemeInput& in) { return simple(in, twice); }), "<no error>");
  twice.times = 3;
  EXPECT_NE(run_custom("twice", [&](const SchemeInput& in) { return simple(in, twice); })
                .find("was rasterised 3 times, more than the scheme declared (twice)"),
            std::string::npos);
}

TEST(Conservation, WorkWithoutItsDrawIsAnError) {
  Breaks none;
  none.command = false;
  std::string m = run_custom("headless", [&](const SchemeInput& in) { return simple(in, none); });
  EXPECT_EQ(m.rfind("scheme 'simple' breaks a conservation law (each draw's work runs under a draw its GPM received for "
                    "it): object 0's geometry ran on GPM 0, whose front end had received no draw (and ",
                    0),
            0u)
      << m;
  Breaks shared;
  shared.draw_every = 2;
  m = run_custom("shared", [&](const SchemeInput& in) { return simple(in, shared); });
  EXPECT_NE(m.find("object 1's geometry ran on GPM 0 under the draw its front end received for object 0"), std::string::npos)
      << m;
}

TEST(Conservation, PixelsNotComposedOrComposedTwiceAreAnError) {
  Breaks lost;
  lost.private_buffer = true;
  std::string m = run_custom("lost", [&](const SchemeInput& in) { return simple(in, lost); });
  EXPECT_NE(m.find("(every pixel of the final frame composed once)"), std::string::npos) << m;
  EXPECT_NE(m.find("was written into private framebuffer 1 and never composed"), std::string::npos) << m;
  lost.compositions = 2;
  m = run_custom("lost", [&](const SchemeInput& in) { return simple(in, lost); });
  EXPECT_NE(m.find("was written into private framebuffer 1 once and composed twice"), std::string::npos) << m;
  Breaks again;
  again.compositions = 1;  // written into the final frame and merged there too
  m = run_custom("again", [&](const SchemeInput& in) { return simple(in, again); });
  EXPECT_NE(m.find("was written into the final framebuffer and composed there once more"), std::string::npos) << m;
}

TEST(Conservation, AFramesPixelsBelongInItsOwnFinalFramebuffer) {
  // AFR-like: two frames in flight, frame 1 written into frame 0's buffer.
  const Frames& fr = frames("courtyard");
  const auto afr_like = [](const SchemeInput& in) {
    FrameSim sim(in, 2);
    for (int k = 0; k < 2; ++k) {
      const FrameTrace& f = sim.frame(k);
      const std::vector<ObjectRecords> objects = records_by_object(f, sim.scene().objects.size());
      for (uint32_t o = 0; o < objects.size(); ++o) {
        sim.command(k);
        const int geo = sim.geometry(k, o, 1, 0);
        for (int e = 0; e < 2; ++e)
          if (!objects[o].eye[e].empty()) (void)sim.tiles(k, objects[o].eye[e], 0, f, {geo});
        sim.end_draw(k);
      }
    }
    return sim.finish("afr-like", 2);
  };
  const std::string m = test::message_of([&] {
    (void)run_scheme({"afr-like", std::make_shared<Custom>(afr_like)}, fr.scene, {fr.traces[0], fr.traces[1]}, Config{});
  });
  EXPECT_NE(m.find("frame 1 of the run: object"), std::string::npos) << m;
  EXPECT_NE(m.find("was written into frame 0's final framebuffer"), std::string::npos) << m;
}

TEST(Conservation, ARecordReplayedAsAnotherFramesIsAnError) {
  // Frame 1's records handed over as frame 0's: their texture lines would
  // be read from the wrong frame.
  const Frames& fr = frames("courtyard");
  const auto mixed = [](const SchemeInput& in) {
    FrameSim sim(in);
    const std::vector<ObjectRecords> objects = records_by_object(sim.frame(1), sim.scene().objects.size());
    uint32_t o = 0;
    while (objects[o].eye[0].empty()) ++o;
    sim.command(0);
    (void)sim.tiles(0, objects[o].eye[0], 0, sim.frame(0), {sim.geometry(0, o, 1, 0)});
    return sim.finish("mixed");
  };
  const std::string m = test::message_of([&] {
    (void)run_scheme({"mixed", std::make_shared<Custom>(mixed)}, fr.scene, {fr.traces[0], fr.traces[1]}, Config{});
  });
  EXPECT_NE(m.find("scheme 'mixed' breaks a conservation law (every covered fragment rasterised once per eye): object "),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("was rasterised on GPM 0 as part of a frame it is not of"), std::string::npos) << m;
}

TEST(Conservation, AResultNotMadeByFinishIsRefused) {
  const std::string m = run_custom("forged", [](const SchemeInput&) {
    SchemeResult r;
    r.frame_latency_s = 1e-3;
    return r;
  });
  EXPECT_EQ(m, "scheme 'forged' returned a result that FrameSim::finish did not make, so its conservation laws were not checked");
}

TEST(Conservation, ChecksCanBeTurnedOffForBenchmarksOnly) {
  FrameSim::set_law_checks(false);
  const std::string m = run_custom("idle", [](const SchemeInput& in) { return FrameSim(in).finish("idle"); });
  FrameSim::set_law_checks(true);
  EXPECT_EQ(m, "<no error>");
  EXPECT_TRUE(FrameSim::law_checks());
}

}  // namespace
}  // namespace oovr
