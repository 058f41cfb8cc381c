// baseline (paper Section 3, "single programming model"): the whole system
// is one GPU, and "the VR rendering workloads are sequentially launched and
// distributed to different GPMs without specific scheduling". Draws are
// issued in order and every GPM receives each one (its state and commands);
// each eye goes to a group of GPMs (the first half of the GPMs renders the
// left eye, the second half the right), and an eye's 16x16 screen tiles are
// dealt over its group tile by tile (sort_first.h), as a GPU interleaves
// tiles over its raster engines, so the GPMs of a group share the eye's
// colour and depth pages (the depth-test traffic between GPMs of Section
// 6.2). Geometry runs once per draw (SMP), on the GPM the draw index
// selects, and set-up triangles are handed to the GPMs owning their tiles.
// Placement is first touch with a remote cache (MCM-GPU), from the
// configuration. `baseline-paged` deals whole framebuffer pages instead.
//
// Derived from the trace: each tile record goes to its tile's owner (texture,
// depth and colour lines, fragments, quads, lookups); each object's set-up
// triangles of both eyes are set up once, and the triangles binned to a
// GPM's tiles are what it receives. Duplicates nothing.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class Baseline final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(sim, eye_groups_by_tile(sim.gpms(), sim.frame()), Geometry::shared);
    return sim.finish("baseline");
  }
};

const Schemes::Add reg("baseline", {"one GPU: eyes to GPM groups, tiles dealt one by one, SMP geometry once per draw",
                                    [] { return std::make_unique<Baseline>(); }, 10});

}  // namespace
}  // namespace oovr
