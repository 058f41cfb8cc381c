// baseline-1tb (paper Section 3, Figure 4): the baseline with 1 TB/s links,
// as fast as local DRAM, which bounds what better locality can gain.
//
// Derived from the trace: as baseline.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class Baseline1Tb final : public Scheme {
 public:
  void configure(MachineSpec& m) const override {
    m.memory.link_bandwidth = BytesPerSecond{1e12};
    m.set_entry("link.bandwidth", format_bandwidth(m.memory.link_bandwidth), m.memory.link_bandwidth.value);
  }
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(sim, eye_groups_by_tile(sim.gpms(), sim.frame()), Geometry::shared);
    return sim.finish("baseline-1tb");
  }
};

const Schemes::Add reg("baseline-1tb",
                       {"the baseline with 1 TB/s links", [] { return std::make_unique<Baseline1Tb>(); }, 20, {}, "baseline"});

}  // namespace
}  // namespace oovr
