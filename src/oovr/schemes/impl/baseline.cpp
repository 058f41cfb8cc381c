// baseline (paper Section 3, "single programming model"): the whole system
// is one GPU. Draws are issued in order; each eye goes to a group of GPMs
// (the first half of the GPMs renders the left eye, the second half the
// right), and an eye's 16x16 screen tiles are interleaved over its group by
// framebuffer block (the 8x8 tiles of one 64 KB page), so that first touch
// makes each GPM's framebuffer local rather than shared page by page.
// Geometry runs once per draw (SMP), on the GPM the draw index selects, and
// set-up triangles go to the GPMs owning their tiles. Placement is first
// touch with a remote cache (MCM-GPU), from the configuration.
//
// Derived from the trace: each tile record goes to its tile's owner (texture,
// depth and colour lines, fragments, quads, lookups); each object's set-up
// triangles of both eyes are set up once, and the triangles binned to a
// GPM's tiles are what it receives. Duplicates nothing.
#include "oovr/schemes/frame_sim.h"

namespace oovr {
namespace {

class Baseline final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(sim, eye_groups_interleaved(sim.gpms(), sim.layout()), Geometry::shared);
    return sim.finish("baseline");
  }
};

const Schemes::Add reg("baseline", {"one GPU: eyes to GPM groups, tiles interleaved, SMP geometry once per draw",
                                    [] { return std::make_unique<Baseline>(); }});

}  // namespace
}  // namespace oovr
