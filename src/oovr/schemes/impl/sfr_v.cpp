// sfr-v (paper Section 4.2, tile-level SFR with vertical strips): the stereo
// frame is cut into one vertical strip of tiles per GPM, so the eyes end up
// on different GPMs and SMP cannot share geometry between them. Each GPM
// processes every draw that overlaps its strip (the whole draw's geometry,
// once per eye it covers: primitive duplication) and renders its strip.
//
// Derived from the trace: each tile record goes to the GPM owning its strip;
// a draw's vertices are repeated per eye on every GPM whose strip it
// reaches, with that eye's set-up triangles. Duplicates geometry by
// definition, never fragments.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class SfrV final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    const int n = sim.gpms(), tiles_x = sim.frame().tiles_x;
    sort_first(
        sim, [&](int tx, int, int) { return vertical_strip_owner(tx, tiles_x, n); }, Geometry::duplicated_per_eye);
    return sim.finish("sfr-v");
  }
};

const Schemes::Add reg("sfr-v", {"tile SFR, one vertical strip per GPM (eyes apart, no SMP sharing)",
                                 [] { return std::make_unique<SfrV>(); }, 50});

}  // namespace
}  // namespace oovr
