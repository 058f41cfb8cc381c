// object (paper Section 4.3, object-level SFR, sort-last): objects go to
// GPMs round-robin, one at a time per GPM, and the left and right views of
// an object are separate tasks (geometry twice, no SMP). Each GPM renders
// into its own colour and depth buffer in its local DRAM; the textures an
// object samples are placed by first touch, so data tends to live where its
// objects render. "Once a worker completes the assembled object, the output
// color in its local DRAM is sent to the root node to composite the final
// frame": after each object, a worker sends the colour and depth of every
// line the object wrote to the root, GPM 0, whose ROPs merge them by depth
// while the root goes on rendering its own objects (Section 5.3: the colour
// output runs asynchronously with shading, but one GPM's ROPs limit the
// pixel rate). The root's own objects are drawn straight into the frame.
//
// Derived from the trace: per object and eye, its tile records (work, texture
// lines, depth and colour lines) and its set-up triangles; the lines each
// object wrote decide the composition bytes and pixels.
#include <bit>

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
    const uint64_t pixels_per_line = f.line_bytes / 4;
    for (uint32_t o = 0; o < objects.size(); ++o) {
      const int g = int(o % uint32_t(n));
      uint64_t lines = 0;
      for (int e = 0; e < 2; ++e) {
        if (objects[o].eye[e].empty()) continue;
        const int geo = sim.geometry(g, o, 1, f.objects[o].setup[e]);
        sim.tiles(g, objects[o].eye[e], g, f, {geo});
        for (const TileWork* r : objects[o].eye[e]) lines += uint64_t(std::popcount(r->write_mask));
      }
      if (g == 0 || lines == 0) continue;
      // Colour and depth of the object's lines, then the root's depth merge.
      const int sent = sim.transfer(g, 0, lines * f.line_bytes * 2, Category::composition, {sim.last_unit(g)});
      sim.compose(0, lines * pixels_per_line, {sent});
    }
    return sim.finish("object");
  }
};

const Schemes::Add reg("object", {"object-level SFR: objects round-robin, eyes separate, root composition",
                                  [] { return std::make_unique<ObjectLevel>(); }});

}  // namespace
}  // namespace oovr
