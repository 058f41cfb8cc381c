// object (paper Section 4.3, object-level SFR, sort-last): objects go to
// GPMs round-robin, one at a time per GPM, and the left and right views of
// an object are separate tasks (each a draw of its own: received and
// transformed per view, no SMP). Each GPM renders into its own buffer in its
// local DRAM; the textures an object samples are placed by first touch, so
// data tends to live where its objects render. "Once a worker completes the
// assembled object, the output color in its local DRAM is sent to the root
// node to composite the final frame": after each view, a worker sends what
// it wrote (schemes/composition.h: colour, per line, by default) to the
// root, GPM 0, whose ROPs merge it while the root goes on rendering its own
// objects (Section 5.3: the colour output runs asynchronously with shading,
// but one GPM's ROPs limit the pixel rate). The root's own objects are
// drawn straight into the final frame. That is the gather algorithm;
// sort_last.composition picks another (schemes/composition.h).
//
// Derived from the trace: per object and view, its tile records (work,
// texture lines, depth and colour lines) and its set-up triangles; the
// lines and fragments each view wrote decide the composition bytes and
// pixels.
#include "oovr/schemes/composition.h"

namespace oovr {
namespace {

class ObjectLevel final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    const int n = in.spec->memory.gpms;
    FrameSim sim(in, sort_last_framebuffers(n));
    Composer composer(sim, sim.spec().composition, CompositionAlgorithm::gather);
    const FrameTrace& f = sim.frame();
    const std::vector<ObjectRecords> objects = records_by_object(f, sim.draws(f).size());
    for (uint32_t o = 0; o < objects.size(); ++o) {
      const int g = int(o % uint32_t(n));
      for (int e = 0; e < 2; ++e) {
        sim.command(g);
        const int geo = sim.geometry(g, o, 1, f.objects[o].setup[e]);
        if (!objects[o].eye[e].empty()) {
          FrameSim::TileJob job{g, objects[o].eye[e], 0, {geo}};
          composer.target(job);
          composer.send(job, sim.tiles_together({job}, f).front());
        }
        sim.end_draw(g);
      }
    }
    composer.close();
    return sim.finish("object");
  }
};

const Schemes::Add reg("object", {"object-level SFR: objects round-robin, eyes separate, root composition",
                                  [] { return std::make_unique<ObjectLevel>(); },
                                  70,
                                  {"sort_last"}});

}  // namespace
}  // namespace oovr
