// ideal: one GPU with N times the resources of a GPM (SMs, raster, ROPs,
// L2, DRAM bandwidth) and no NUMA: an upper bound for N GPMs.
//
// Derived from the trace: every record and object on the one big GPU, as
// single-gpm does on one GPM. Duplicates nothing.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class Ideal final : public Scheme {
 public:
  void configure(MachineSpec& m) const override {
    const int64_t n = m.memory.gpms;
    const auto scale = [&](int& field, const char* key) {
      field = int(field * n);
      m.set_entry(key, std::to_string(field), double(field));
    };
    scale(m.memory.sms_per_gpm, "gpm.sms");
    scale(m.timing.rops, "gpm.rops");
    scale(m.timing.raster_fragments_per_clock, "gpm.raster_fragments_per_clock");
    scale(m.timing.setup_triangles_per_clock, "gpm.setup_triangles_per_clock");
    // N times the L2 as N times the ways: the same sets, always valid.
    m.memory.l2.size = Bytes{m.memory.l2.size.value * uint64_t(n)};
    m.set_entry("cache.l2.size", format_bytes(m.memory.l2.size), double(m.memory.l2.size.value));
    scale(m.memory.l2.ways, "cache.l2.ways");
    m.memory.dram_bandwidth = BytesPerSecond{m.memory.dram_bandwidth.value * double(n)};
    m.set_entry("dram.bandwidth", format_bandwidth(m.memory.dram_bandwidth), m.memory.dram_bandwidth.value);
    m.memory.gpms = 1;
    m.set_entry("gpms", "1", 1.0);
  }
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(
        sim, [](int, int, int) { return 0; }, Geometry::shared);
    return sim.finish("ideal");
  }
};

const Schemes::Add reg("ideal",
                       {"one GPU with N times a GPM's resources, no NUMA", [] { return std::make_unique<Ideal>(); }, 110});

}  // namespace
}  // namespace oovr
