// two-pass: one GPM renders the two views one after the other, every draw
// once per view (no SMP): stereo as engines did before single-pass stereo.
// Against `single-gpm` (the same GPM with SMP) it measures what SMP saves
// (the paper's Section 3 reports 27% over rendering the two views in
// sequence).
//
// Derived from the trace: the left view's work of every draw, then the
// right view's. The application issues every draw in each view, so each is
// received and transformed once per view whether or not the view shows it
// (as single-gpm transforms every draw once): twice single-gpm's draws and
// vertices, each view with its own set-up triangles. Duplicates vertex work
// and draws by definition, never fragments.
#include "oovr/schemes/frame_sim.h"

namespace oovr {
namespace {

class TwoPass final : public Scheme {
 public:
  void configure(MachineSpec& m) const override {
    m.memory.gpms = 1;
    m.set_entry("gpms", "1", 1.0);
  }
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    const FrameTrace& f = sim.frame();
    const std::vector<ObjectRecords> objects = records_by_object(f, sim.draws(f).size());
    for (int e = 0; e < 2; ++e)
      for (uint32_t o = 0; o < objects.size(); ++o) {
        sim.command(0);
        const int geo = sim.geometry(0, o, 1, f.objects[o].setup[e]);
        if (!objects[o].eye[e].empty()) sim.tiles(0, objects[o].eye[e], 0, f, {geo});
        sim.end_draw();
      }
    return sim.finish("two-pass");
  }
};

const Schemes::Add reg("two-pass", {"one GPM, the two views rendered one after the other (no SMP)",
                                    [] { return std::make_unique<TwoPass>(); }, 120});

}  // namespace
}  // namespace oovr
