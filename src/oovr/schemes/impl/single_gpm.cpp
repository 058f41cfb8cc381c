// single-gpm: one GPM of the configured machine renders the frame alone
// (SMP, everything local): the unit the scaling studies normalise by.
//
// Derived from the trace: every record and object, in draw order, on GPM 0.
// Duplicates nothing.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class SingleGpm final : public Scheme {
 public:
  void configure(MachineSpec& m) const override {
    m.memory.gpms = 1;
    m.set_entry("gpms", "1", 1.0);
  }
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(
        sim, [](int, int, int) { return 0; }, Geometry::shared);
    return sim.finish("single-gpm");
  }
};

const Schemes::Add reg("single-gpm", {"one GPM alone", [] { return std::make_unique<SingleGpm>(); }, 100});

}  // namespace
}  // namespace oovr
