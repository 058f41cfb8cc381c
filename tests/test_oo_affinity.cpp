// oo-vr-affinity (schemes/impl/oo.cpp): OO-VR whose engine weighs the link
// time of a batch's pixels outside each GPM's strip, as its objects' pixels
// fell in the previous frame. The engine's choice is worked by hand in
// test_framework.cpp (ScreenAffinityTradesPredictedWaitForLinkTime); here,
// the scheme on the machine.
#include <gtest/gtest.h>

#include <memory>

#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& courtyard() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("courtyard", 320, 480, 30, 4);
  return *r;
}

double own(const SchemeResult& r, const std::string& name) {
  const Stat* s = r.stats.find(r.scheme, name);
  return s ? s->value : -1;
}

TEST(OOAffinity, WeightZeroIsOOVR) {
  const auto& r = courtyard();
  Config off;
  off.set("oo.affinity=0");
  const SchemeResult a = run_scheme_window("oo-vr-affinity", r.scene, r.traces, off, 4);
  const SchemeResult vr = run_scheme_window("oo-vr", r.scene, r.traces, Config(), 4);
  EXPECT_EQ(a.frame_latencies_s, vr.frame_latencies_s);
  EXPECT_EQ(a.inter_gpm_bytes, vr.inter_gpm_bytes);
  EXPECT_EQ(own(a, "affine_batches"), -1) << "off: no such statistic";
}

TEST(OOAffinity, ItsChoicesDifferOnceAFrameHasBeenSeen) {
  const auto& r = courtyard();
  // A frame on its own has no previous frame: OO-VR's choices, its frame.
  const SchemeResult cold = run_scheme("oo-vr-affinity", r.scene, {r.traces.at(0)}, Config());
  const SchemeResult cold_vr = run_scheme("oo-vr", r.scene, {r.traces.at(0)}, Config());
  EXPECT_EQ(cold.frame_latency_s, cold_vr.frame_latency_s);
  EXPECT_EQ(own(cold, "affine_batches"), 0);
  // In a window, after the warm-up pass, the table sends some batches
  // elsewhere than the GPM predicted free first, and every fragment is
  // still rendered once (the conservation checks run with every scheme).
  const SchemeResult warm = run_scheme_window("oo-vr-affinity", r.scene, r.traces, Config(), 4);
  EXPECT_GT(own(warm, "affine_batches"), 0);
  const SchemeResult vr = run_scheme_window("oo-vr", r.scene, r.traces, Config(), 4);
  EXPECT_EQ(warm.covered_fragments, vr.covered_fragments);
  EXPECT_NE(warm.frame_latencies_s, vr.frame_latencies_s);
}

TEST(OOAffinity, AWeightOutsideItsRangeIsRefused) {
  const auto& r = courtyard();
  for (const char* bad : {"oo.affinity=-1", "oo.affinity=1001", "oo.affinity=abc"}) {
    Config c;
    c.set(bad);
    EXPECT_THROW(run_scheme_window("oo-vr-affinity", r.scene, r.traces, c, 4), Error) << bad;
  }
}

}  // namespace
}  // namespace oovr
