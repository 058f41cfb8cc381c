// sfr-lb (schemes/impl/sfr_lb.cpp): sfr-v's strips, moved each frame
// towards the split that would have balanced the frame before, damped.
#include <gtest/gtest.h>

#include <memory>

#include "oovr/scene/builtin.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

// The courtyard at 320x480 per eye: 40 tile columns in the stereo frame.
const test::RenderedFrames& courtyard() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("courtyard", 320, 480, 30, 4);
  return *r;
}

Config with(std::initializer_list<const char*> settings) {
  Config c;
  for (const char* s : settings) c.set(s);
  return c;
}

// A frame on its own is split evenly: 10 columns per GPM, sfr-v's strips,
// and so sfr-v's frame.
TEST(SfrLb, AColdFrameIsSfrV) {
  const auto& r = courtyard();
  ASSERT_EQ(r.traces[0]->tiles_x, 40);
  const SchemeResult lb = run_scheme("sfr-lb", r.scene, {r.traces[0]}, Config{});
  const SchemeResult v = run_scheme("sfr-v", r.scene, {r.traces[0]}, Config{});
  EXPECT_EQ(lb.frame_latency_s, v.frame_latency_s);
  EXPECT_EQ(lb.inter_gpm_bytes, v.inter_gpm_bytes);
  EXPECT_EQ(lb.vertices, v.vertices);
  EXPECT_EQ(lb.stats.at("sfr-lb", "bound.1"), 10);
  EXPECT_EQ(lb.stats.at("sfr-lb", "bound.3"), 30);
}

// Two GPMs, 20 columns each: the next boundary is where half the frame's
// busy time falls, each strip's time spread evenly over its columns, moved
// 1 - damping of the way from 20; the next frame renders with it.
TEST(SfrLb, TheBoundaryMovesToWhereHalfTheTimeFallsDamped) {
  const auto& r = courtyard();
  for (const char* damping : {"0", "0.5", "1"}) {
    Config d = with({"gpms=2", "gpm.draw_cycles=0"});
    d.set(std::string("sfr_lb.damping=") + damping);
    const auto carried = std::make_shared<CarriedState>();
    const SchemeResult first = run_scheme("sfr-lb", r.scene, {r.traces[0]}, d, carried);
    const double t0 = first.gpm_busy_s[0], t1 = first.gpm_busy_s[1], half = (t0 + t1) / 2;
    ASSERT_GT(t0, 0);
    ASSERT_GT(t1, 0);
    const double target = t0 >= half ? 20 * half / t0 : 20 + 20 * (half - t0) / t1;
    const double keep = std::stod(damping);
    const std::vector<double> bounds = carried->values.at("sfr-lb.bounds");
    ASSERT_EQ(bounds.size(), 3u);
    EXPECT_EQ(bounds[0], 0);
    EXPECT_NEAR(bounds[1], keep * 20 + (1 - keep) * target, 1e-9) << damping;
    EXPECT_EQ(bounds[2], 40);
    if (keep < 1) {
      EXPECT_NE(bounds[1], 20) << "the courtyard's eyes cost unevenly";
    }
    const SchemeResult second = run_scheme("sfr-lb", r.scene, {r.traces[1]}, d, carried);
    EXPECT_EQ(second.stats.at("sfr-lb", "bound.1"), bounds[1]);
  }
}

// Over a window (after its warm-up pass) the strips follow the load: the
// GPMs are more even than sfr-v's fixed strips leave them. (Without the
// per-draw cost, which every GPM pays alike, the courtyard's fragment work
// is what differs between strips.)
TEST(SfrLb, AWindowIsBetterBalancedThanFixedStrips) {
  const auto& r = courtyard();
  const Config c = with({"gpm.draw_cycles=0"});
  const SchemeResult lb = run_scheme_window("sfr-lb", r.scene, r.traces, c, 4);
  const SchemeResult v = run_scheme_window("sfr-v", r.scene, r.traces, c, 4);
  EXPECT_GT(v.best_to_worst(), 1.2);
  EXPECT_LT(lb.best_to_worst(), v.best_to_worst());
  EXPECT_LT(lb.frame_latency_s, v.frame_latency_s);
  // With the damping at 1 the strips never move: sfr-v's window.
  const SchemeResult still = run_scheme_window("sfr-lb", r.scene, r.traces, with({"gpm.draw_cycles=0", "sfr_lb.damping=1"}), 4);
  EXPECT_EQ(still.frame_latency_s, v.frame_latency_s);
}

TEST(SfrLb, ADampingOutsideZeroToOneIsRefused) {
  const auto& r = courtyard();
  EXPECT_NE(test::message_of([&] {
              (void)run_scheme("sfr-lb", r.scene, {r.traces[0]}, with({"sfr_lb.damping=1.5"}));
            }).find("sfr_lb.damping"),
            std::string::npos);
}

}  // namespace
}  // namespace oovr
