// object (paper Section 4.3, object-level SFR, sort-last): objects go to
// GPMs round-robin, one at a time per GPM, and the left and right views of
// an object are separate tasks (geometry twice, no SMP). Each GPM renders
// into its own colour and depth buffer; the textures an object samples are
// placed by first touch, so data tends to live where its objects render.
// When all are done, every GPM sends the pixels it wrote (colour and depth)
// to the root, GPM 0, whose ROPs merge them by depth into the final frame.
#include <set>

#include "oovr/schemes/frame_sim.h"

namespace oovr {
namespace {

class ObjectLevel final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    const int n = int(in.config.get_int("gpms", MemorySpec{}.gpms));
    FrameSim sim(in, n);
    const FrameTrace& f = sim.frame();
    const std::vector<ObjectRecords> objects = records_by_object(f, sim.scene().objects.size());
    // (tile, line) pairs each GPM wrote: what it must send to the root.
    std::vector<std::set<uint64_t>> written(static_cast<size_t>(n));
    for (uint32_t o = 0; o < objects.size(); ++o) {
      const int g = int(o % uint32_t(n));
      for (int e = 0; e < 2; ++e) {
        if (objects[o].eye[e].empty()) continue;
        const int geo = sim.geometry(g, o, 1, f.objects[o].setup[e]);
        sim.tiles(g, objects[o].eye[e], g, f, {geo});
        for (const TileWork* r : objects[o].eye[e])
          for (uint32_t m = r->write_mask; m; m &= m - 1)
            written[size_t(g)].insert((uint64_t(r->tile_y) * uint64_t(f.tiles_x) + r->tile_x) * 64 + uint64_t(__builtin_ctz(m)));
      }
    }
    // Root composition: colour and depth of every line a worker wrote.
    const uint64_t pixels_per_line = f.line_bytes / 4;
    std::vector<int> arrived{sim.last_unit(0)};
    uint64_t pixels = 0;
    for (int g = 1; g < n; ++g) {
      if (written[size_t(g)].empty()) continue;
      const uint64_t lines = written[size_t(g)].size();
      arrived.push_back(sim.transfer(g, 0, lines * f.line_bytes * 2, Category::composition, {sim.last_unit(g)}));
      pixels += lines * pixels_per_line;
    }
    if (pixels) sim.compose(0, pixels, arrived);
    return sim.finish("object");
  }
};

const Schemes::Add reg("object", {"object-level SFR: objects round-robin, eyes separate, root composition",
                                  [] { return std::make_unique<ObjectLevel>(); }});

}  // namespace
}  // namespace oovr
