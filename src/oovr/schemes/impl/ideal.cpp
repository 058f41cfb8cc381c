// ideal: one GPU with N times the resources of a GPM (SMs, raster, ROPs,
// L2, DRAM bandwidth) and no NUMA: an upper bound for N GPMs.
//
// Derived from the trace: every record and object on the one big GPU, as
// single-gpm does on one GPM. Duplicates nothing.
#include <cstdio>

#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class Ideal final : public Scheme {
 public:
  void configure(Config& c) const override {
    const MemorySpec d;
    const TimingSpec t;
    // Read in the ranges their components accept (so the products fit).
    const int64_t n = c.get_int("gpms", d.gpms, 1, kMaxGpms);
    const auto scale = [&](const char* key, int64_t value) { c.set(key, std::to_string(value * n)); };
    scale("gpm.sms", c.get_int("gpm.sms", d.sms_per_gpm, 1, 1024));
    scale("gpm.rops", c.get_int("gpm.rops", t.rops, 1, 1000000));
    scale("gpm.raster_fragments_per_clock",
          c.get_int("gpm.raster_fragments_per_clock", t.raster_fragments_per_clock, 1, 1000000));
    scale("gpm.setup_triangles_per_clock", c.get_int("gpm.setup_triangles_per_clock", t.setup_triangles_per_clock, 1, 1000000));
    // N times the L2 as N times the ways: the same sets, always valid.
    const Bytes l2 = c.get_bytes("cache.l2.size", d.l2.size);
    c.set("cache.l2.size", std::to_string(l2.value * uint64_t(n)));
    scale("cache.l2.ways", c.get_int("cache.l2.ways", d.l2.ways, 1, 1024));
    char bw[64];
    std::snprintf(bw, sizeof bw, "%.17gBps", c.get_bandwidth("dram.bandwidth", d.dram_bandwidth).value * double(n));
    c.set("dram.bandwidth", bw);
    c.set("gpms", "1");
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
