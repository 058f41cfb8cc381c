// Sort-first rendering (DESIGN.md, "Schemes"): every screen tile of the
// frame has an owner GPM that rasterises, shades and writes it; the schemes
// that split the screen (baseline, tile SFR) and those with one GPM
// (single-gpm, ideal) differ only in who owns which tile and where geometry
// runs.
#pragma once

#include <functional>

#include "oovr/schemes/frame_sim.h"

namespace oovr {

enum class Geometry {
  // Once per draw on one GPM (draw index modulo the GPMs), SMP for both
  // eyes; set-up triangles are handed to the GPMs owning their tiles.
  shared,
  // On every GPM that owns tiles the draw covers: the whole draw, SMP for
  // both eyes (primitive duplication, tile SFR with horizontal strips).
  duplicated_smp,
  // The same, but once per eye covered, without SMP (vertical strips
  // separate the eyes).
  duplicated_per_eye,
};

// Who owns a tile: (tile_x, tile_y, eye) -> GPM.
using TileOwner = std::function<int(int tile_x, int tile_y, int eye)>;

// Renders frames[0] sort-first, draw by draw. Every GPM receives every draw
// (the command stream is broadcast: each GPM must hold every draw's state),
// and the draw ends on every GPM before the next begins.
void sort_first(FrameSim& sim, const TileOwner& owner, Geometry geometry);

// The paper's baseline (Section 3: the system is one GPU, work distributed
// "without specific scheduling"): the first half of the GPMs renders the
// left eye, the second half the right (one GPM renders both when there is
// one); an eye's 16x16 tiles are dealt over its half tile by tile, (x + y)
// modulo the half's size: a checkerboard on two GPMs, diagonals on more, as
// a GPU interleaves screen tiles over its raster engines. Colour and depth
// pages are then shared by the GPMs of a half.
TileOwner eye_groups_by_tile(int gpms, const FrameTrace& frame);
// The page-aware variant (`baseline-paged`): an eye's framebuffer blocks
// (the tiles of one page) are dealt over its half the same way, block by
// block, so that first touch makes each GPM's pixels local.
TileOwner eye_groups_by_page(int gpms, const FrameTrace& frame, const SceneLayout& layout);

// Vertical strips of whole tile columns, one per GPM (the last may be
// narrower): the owner of tile column `tile_x` (tile SFR-V, and OO-VR's
// distributed framebuffer, which maps memory as SFR-V does: Section 5.3).
inline int vertical_strip_owner(int tile_x, int tiles_x, int gpms) {
  const int width = (tiles_x + gpms - 1) / gpms;
  return std::min(gpms - 1, tile_x / width);
}

}  // namespace oovr
