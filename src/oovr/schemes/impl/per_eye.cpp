// per-eye (not in the OO-VR paper): each eye on its own GPMs, as VR drivers
// ship it (NVIDIA VR SLI, AMD LiquidVR affinity multi-GPU): the
// application submits each draw once with a mask of the GPUs it goes to,
// and each GPU renders it from its own eye's view. The first half of the
// GPMs renders the left eye, the rest the right (one GPM renders both when
// there is one; with an odd count the right eye has the larger half).
//
// A draw goes to the GPMs of its mask: every GPM when the halves split
// their eyes by tiles, the GPM rendering it in each eye when they split
// them by objects. Each transforms the draw's vertices for its own eye:
// a GPU cannot know that a draw misses its view before transforming it, and
// the eyes are on different GPMs, so SMP shares nothing between them (the
// vertex work of two sequential views, spread over the machine). The eyes
// never compose with each other: each eye's image stays where it was
// rendered, as the other schemes' final frames do (scan-out to the
// display is modelled for none).
//
// With more than one GPM per eye, `per_eye.split` says how a half shares
// its eye (the drivers leave this to the application):
//   tiles    the eye's 16x16 tiles dealt over its half as the baseline
//            deals them (eye_groups_by_tile); every GPM of the half
//            transforms and sets up every draw for the eye (primitive
//            duplication, as SLI's split-frame rendering) and renders its
//            tiles. No composition.
//   objects  the eye's objects dealt round-robin over its half, each sent
//            to and transformed once on its GPM; the half's first GPM owns the
//            eye's final image and the others send it what they wrote after
//            each object (sort-last, schemes/composition.h, as object-level
//            SFR composes on its root).
//
// Assumed where the drivers are silent: the split of a half (they offer
// two GPUs, one per eye), and no cost for the per-GPU view constants.
#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/schemes/composition.h"
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

struct PerEyeSettings {
  bool objects = false;  // per_eye.split: "objects", else "tiles"

  static PerEyeSettings from_config(const Config& c) {
    return {c.get_choice("per_eye.split", "tiles", {"tiles", "objects"}) == "objects"};
  }
};

// The GPMs of eye `e`: [first, first + size).
struct Half {
  int first, size;
};
Half half_of(int gpms, int eye) {
  if (gpms < 2) return {0, 1};
  const int left = gpms / 2;
  return eye == 0 ? Half{0, left} : Half{left, gpms - left};
}

class PerEye final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    const bool objects = in.spec->own<PerEyeSettings>("per_eye").objects;
    const int n = in.spec->memory.gpms;
    FrameSim sim(in, objects ? sort_last_framebuffers(n) : 1);
    const FrameTrace& f = sim.frame();
    const std::vector<ObjectRecords> records = records_by_object(f, sim.draws(f).size());
    if (objects) {
      // The eye's final image belongs to the first GPM of its half.
      const int right_tiles = (f.frame_width / 2) / f.tile_size;
      Composer composer(sim, sim.spec().composition, [&](int tx, int) { return half_of(n, tx < right_tiles ? 0 : 1).first; });
      for (uint32_t o = 0; o < records.size(); ++o) {
        // The draw's mask: the GPM rendering it in each eye.
        int at[2];
        for (int e = 0; e < 2; ++e) {
          const Half h = half_of(n, e);
          at[e] = h.first + int(o % uint32_t(h.size));
        }
        sim.command(at[0]);
        if (at[1] != at[0]) sim.command(at[1]);
        std::vector<FrameSim::TileJob> jobs;
        for (int e = 0; e < 2; ++e) {
          const int geo = sim.geometry(at[e], o, 1, f.objects[o].setup[e]);
          if (records[o].eye[e].empty()) continue;
          jobs.push_back({at[e], records[o].eye[e], 0, {geo}});
          composer.target(jobs.back());
        }
        const std::vector<int> units = sim.tiles_together(jobs, f);
        for (size_t k = 0; k < jobs.size(); ++k) composer.send(jobs[k], units[k]);
        sim.end_draw(at[0]);
        if (at[1] != at[0]) sim.end_draw(at[1]);
      }
    } else {
      const TileOwner owner = eye_groups_by_tile(n, f);
      std::vector<std::vector<const TileWork*>> mine(static_cast<size_t>(n));
      for (uint32_t o = 0; o < records.size(); ++o) {
        for (int g = 0; g < n; ++g) sim.command(g);
        for (auto& m : mine) m.clear();
        for (int e = 0; e < 2; ++e)
          for (const TileWork* r : records[o].eye[e]) mine[size_t(owner(r->tile_x, r->tile_y, e))].push_back(r);
        std::vector<FrameSim::TileJob> jobs;
        for (int e = 0; e < 2; ++e) {
          const Half h = half_of(n, e);
          for (int g = h.first; g < h.first + h.size; ++g) {
            // One GPM with both eyes (n = 1) transforms the draw once per eye.
            const int geo = sim.geometry(g, o, 1, f.objects[o].setup[e]);
            std::vector<const TileWork*> eye_tiles;
            for (const TileWork* r : mine[size_t(g)])
              if (r->eye == e) eye_tiles.push_back(r);
            if (!eye_tiles.empty()) jobs.push_back({g, std::move(eye_tiles), 0, {geo}});
          }
        }
        sim.tiles_together(jobs, f);
        sim.end_draw();
      }
    }
    return sim.finish("per-eye");
  }
};

const ConfigSections::Add settings("per_eye",
                                   {"per-eye's settings (VR SLI, LiquidVR affinity multi-GPU)",
                                    nullptr,
                                    {{"per_eye.split",
                                      "how the GPMs of an eye share it: tiles (dealt as the baseline's) or objects (round-robin, "
                                      "composed on the half's first GPM) (assumed)"}},
                                    true,
                                    [](const Config& c) { return std::any(PerEyeSettings::from_config(c)); }});

const Schemes::Add reg("per-eye", {"each eye on its own half of the GPMs (VR SLI, LiquidVR), draws broadcast",
                                   [] { return std::make_unique<PerEye>(); },
                                   130,
                                   {"per_eye"}});

}  // namespace
}  // namespace oovr
