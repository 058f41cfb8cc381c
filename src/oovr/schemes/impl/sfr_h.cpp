// sfr-h (paper Section 4.2, tile-level SFR with horizontal strips): one
// horizontal strip of tiles per GPM, spanning both eyes, so SMP projects a
// draw's geometry into both eyes at once. Each GPM processes every draw that
// overlaps its strip (the whole draw's geometry: primitive duplication).
//
// Derived from the trace: each tile record goes to the GPM owning its strip;
// a draw's vertices and both eyes' set-up triangles are repeated on every
// GPM whose strip it reaches. Duplicates geometry by definition, never
// fragments.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class SfrH final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    const int n = sim.gpms();
    const int height = (sim.frame().tiles_y + n - 1) / n;
    sort_first(
        sim, [&](int, int ty, int) { return std::min(n - 1, ty / height); }, Geometry::duplicated_smp);
    return sim.finish("sfr-h");
  }
};

const Schemes::Add reg("sfr-h", {"tile SFR, one horizontal strip per GPM spanning both eyes (SMP works)",
                                 [] { return std::make_unique<SfrH>(); }, 60});

}  // namespace
}  // namespace oovr
