// Sort-last composition (paper Sections 4.3 and 5.3), written once for the
// schemes whose GPMs render objects rather than screen tiles (object-level
// SFR, OO_APP, OO-VR). Every pixel of the final frame has an owner GPM (the
// root, or with distributed composition its strip's owner): a GPM writes
// the pixels it owns straight into the final frame and the others into a
// buffer of its own, and after each piece of work sends them to their
// owners, whose ROPs merge them.
//
// What is sent is configuration (docs/model.md argues the default from the
// paper's text):
//   composition.payload      "colour" (default): the paper's "output color
//                            ... sent to the root node" (4.3) and DHC's
//                            "color outputs" (5.3); fragments are then
//                            depth-tested against the final frame's depth
//                            buffer where they are shaded, the "Z-test
//                            during fragment process" traffic of Section
//                            6.2. "colour+depth": sort-last z-compositing,
//                            each GPM keeps its own depth buffer and the
//                            owner merges colour by depth.
//   composition.granularity  "line" (default): whole 128-byte lines of the
//                            framebuffer touched, as every other transfer in
//                            the memory system; "pixel": 4 bytes per passed
//                            fragment and payload (a lower bound).
#pragma once

#include <functional>

#include "oovr/core/config.h"
#include "oovr/schemes/composition_spec.h"
#include "oovr/schemes/frame_sim.h"

namespace oovr {

// Framebuffers of a sort-last scheme: 0 is the final frame, 1 + g GPM g's
// own; build the FrameSim with sort_last_framebuffers(gpms).
inline int sort_last_framebuffers(int gpms) { return gpms + 1; }

class Composer {
 public:
  // `owner(tile_x, tile_y)`: the GPM owning a screen tile's pixels in the
  // final frame. The final frame's colour and depth pages are homed at
  // their owners (the first tile of a page decides), as the paper maps the
  // framebuffer: into the root's DRAM (Section 5.3, "the entire FB is mapped
  // in the DRAM of the master node"), or with DHC as tile SFR-V maps it.
  Composer(FrameSim& sim, CompositionSpec spec, std::function<int(int tile_x, int tile_y)> owner);

  // Sets where `job`'s records write: pixels its GPM owns into the final
  // frame, the others into its own buffer; depth with them when the payload
  // has depth, else in the final frame's depth buffer.
  void target(FrameSim::TileJob& job) const;
  // After `unit` (the job's work), sends the job's pixels owned elsewhere to
  // their owners (a transfer each, category composition) and has the
  // owners' ROPs merge them.
  void send(const FrameSim::TileJob& job, int unit);

  // Bytes and pixels one record sends to its owner (0 when owned locally).
  uint64_t bytes(const TileWork& r) const;
  uint64_t pixels(const TileWork& r) const;

 private:
  FrameSim& m_sim;
  CompositionSpec m_spec;
  std::function<int(int, int)> m_owner;
  int owner(const TileWork& r) const { return m_owner(r.tile_x, r.tile_y); }
};

}  // namespace oovr
