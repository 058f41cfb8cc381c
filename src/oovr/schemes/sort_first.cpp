#include "oovr/schemes/sort_first.h"

namespace oovr {

void sort_first(FrameSim& sim, const TileOwner& owner, Geometry geometry) {
  const FrameTrace& f = sim.frame();
  const std::vector<ObjectRecords> objects = records_by_object(f, sim.draws(f).size());
  const int n = sim.gpms();
  std::vector<std::vector<const TileWork*>> mine(static_cast<size_t>(n));
  for (uint32_t o = 0; o < objects.size(); ++o) {
    for (int g = 0; g < n; ++g) sim.command(g);
    for (auto& m : mine) m.clear();
    std::vector<int> eyes_of(size_t(n), 0);  // bit e: the GPM owns tiles of eye e
    std::vector<uint64_t> triangles_of(size_t(n), 0);
    for (int e = 0; e < 2; ++e)
      for (const TileWork* r : objects[o].eye[e]) {
        const int g = owner(r->tile_x, r->tile_y, e);
        mine[size_t(g)].push_back(r);
        eyes_of[size_t(g)] |= 1 << e;
        triangles_of[size_t(g)] += r->triangles;
      }
    const ObjectWork& ow = f.objects[o];
    std::vector<FrameSim::TileJob> jobs;
    if (geometry == Geometry::shared) {
      // One GPM transforms the draw for both eyes; the owners receive the
      // set-up triangles of their tiles.
      const int geo_gpm = int(o % uint32_t(n));
      const int geo = sim.geometry(geo_gpm, o, 1, uint64_t(ow.setup[0]) + ow.setup[1]);
      for (int g = 0; g < n; ++g)
        if (!mine[size_t(g)].empty())
          jobs.push_back(
              {g, mine[size_t(g)], 0, {geo}, geo_gpm, triangles_of[size_t(g)] * uint64_t(sim.timing().triangle_bytes)});
    } else {
      for (int g = 0; g < n; ++g) {
        if (mine[size_t(g)].empty()) continue;
        const int eyes = __builtin_popcount(unsigned(eyes_of[size_t(g)]));
        uint64_t tris = 0;
        for (int e = 0; e < 2; ++e)
          if (eyes_of[size_t(g)] & (1 << e)) tris += ow.setup[e];
        const int passes = geometry == Geometry::duplicated_smp ? 1 : eyes;
        jobs.push_back({g, mine[size_t(g)], 0, {sim.geometry(g, o, passes, tris)}});
      }
    }
    sim.tiles_together(jobs, f);
    sim.end_draw();
  }
}

namespace {

// The GPMs of an eye (the first half of the GPMs for the left, the rest for
// the right; GPM 0 alone when there is one) and the eye's first tile column.
struct EyeGroup {
  int first, size, first_tile;
};

EyeGroup eye_group(int n, int eye, int frame_width, int tile_size) {
  const int first_tile = eye * (frame_width / 2) / tile_size;
  if (n < 2) return {0, 1, first_tile};
  const int half = n / 2;
  return {eye * half, eye == 0 ? half : n - half, first_tile};
}

}  // namespace

TileOwner eye_groups_by_tile(int n, const FrameTrace& frame) {
  return [n, width = frame.frame_width, tile = frame.tile_size](int tx, int ty, int eye) {
    const EyeGroup g = eye_group(n, eye, width, tile);
    return g.first + (std::max(0, tx - g.first_tile) + ty) % g.size;
  };
}

TileOwner eye_groups_by_page(int n, const FrameTrace& frame, const SceneLayout& layout) {
  return [n, width = frame.frame_width, tile = frame.tile_size, bw = layout.block_w(), bh = layout.block_h()](int tx, int ty,
                                                                                                              int eye) {
    const EyeGroup g = eye_group(n, eye, width, tile);
    // Blocks as the pages lie (from the frame's left edge), counted from the
    // eye's first one.
    return g.first + (tx / bw - g.first_tile / bw + ty / bh) % g.size;
  };
}

}  // namespace oovr
