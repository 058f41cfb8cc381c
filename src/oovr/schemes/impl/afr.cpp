// afr (paper Section 4.1, alternate frame rendering): whole frames
// round-robin over the GPMs, N frames in flight, each GPM rendering its
// frame alone, with SMP, from its own copy of every piece of data
// (replicated placement: no inter-GPM traffic, N times the memory). Reports
// the mean latency of the N frames (each its GPM's time) and the steady
// throughput of N GPMs each rendering one frame after another.
//
// Derived from the trace: N consecutive frames' traces, each whole (every
// draw received and transformed by GPM k, every tile record of frame k on
// GPM k) with its objects' set-up triangles.
// Duplicates nothing within a frame; the data is copied N times.
#include "oovr/schemes/frame_sim.h"

namespace oovr {
namespace {

class Afr final : public Scheme {
 public:
  void configure(MachineSpec& m) const override {
    m.memory.placement = "replicated";
    m.set_entry("memory.placement", m.memory.placement, std::nullopt);
  }
  int frames_needed(int gpms) const override { return gpms; }
  SchemeResult run(const SchemeInput& in) const override {
    const int n = in.spec->memory.gpms;
    if (int(in.frames.size()) < n)
      throw Error("afr needs " + std::to_string(n) + " frames of trace, one per GPM; got " + std::to_string(in.frames.size()));
    FrameSim sim(in, n);
    // Frames are issued in turn: GPM g renders frame g. Units are added
    // draw by draw across the frames so that memory is replayed the way the
    // GPMs would interleave.
    // (A captured game's frames draw different numbers of objects: a GPM
    // whose frame has fewer draws is done with them sooner.)
    std::vector<std::vector<ObjectRecords>> records;
    size_t most = 0;
    for (int g = 0; g < n; ++g) {
      records.push_back(records_by_object(sim.frame(g), sim.draws(sim.frame(g)).size()));
      most = std::max(most, records.back().size());
    }
    for (uint32_t o = 0; o < most; ++o)
      for (int g = 0; g < n; ++g) {
        const FrameTrace& f = sim.frame(g);
        if (o >= records[size_t(g)].size()) continue;
        std::vector<const TileWork*> all = records[size_t(g)][o].both();
        sim.command(g);
        const int geo = sim.geometry(g, o, 1, uint64_t(f.objects[o].setup[0]) + f.objects[o].setup[1], {}, g);
        if (!all.empty()) sim.tiles(g, all, g, f, {geo});
        sim.end_draw(g);
      }
    SchemeResult r = sim.finish("afr", n);
    // A frame's latency is its GPM's time to render it. In steady state
    // each GPM starts its next frame when it finishes one, so N frames come
    // out per mean frame time.
    r.frame_latencies_s = r.gpm_busy_s;
    double sum = 0;
    for (double b : r.gpm_busy_s) sum += b;
    r.frame_latency_s = sum / double(n);
    r.throughput_fps = double(n) / r.frame_latency_s;
    r.notes.push_back(std::to_string(n) + " frames in flight, one per GPM; every GPM holds a copy of all data");
    return r;
  }
};

const Schemes::Add reg("afr", {"alternate frame rendering: a frame per GPM, data replicated",
                               [] { return std::make_unique<Afr>(); }, 40});

}  // namespace
}  // namespace oovr
