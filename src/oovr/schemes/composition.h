// Sort-last composition (paper Sections 4.3 and 5.3), written once for the
// schemes whose GPMs render objects rather than screen tiles (object-level
// SFR, OO_APP, OO-VR, CHOPIN, per-eye split by objects). Every pixel of the
// final frame has an owner GPM: a GPM writes the pixels it owns straight
// into the final frame and the others into a buffer of its own, and the
// composition algorithm brings those to their owners, whose ROPs merge them.
//
// What is sent is configuration (docs/model.md argues the defaults from the
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
// How it is sent is a setting of the schemes that take an algorithm
// (object-level SFR, OO_APP, OO-VR with or without screen affinity, CHOPIN;
// their own section, sort_last):
//   sort_last.composition    "scheme" (default): the scheme's own (object
//                            and OO_APP gather, OO-VR direct send, CHOPIN
//                            pairwise). The others:
//     gather       the root, GPM 0, owns the frame; each piece of work's
//                  pixels go to it as the piece ends (paper 4.3);
//     direct-send  N vertical strips, one per GPM (DHC's, paper 5.3); each
//                  piece's pixels go to their strips' owners as it ends;
//     binary-swap  P = the largest power of two <= N regions, the screen
//                  halved along its longer side log2(P) times; once a GPM
//                  has rendered everything, GPMs P.. first fold their
//                  image into GPM g - P, then in round j GPM g swaps with
//                  g xor P/2^(j+1): it sends what it holds of its
//                  partner's half and merges what it gets of its own (Ma et
//                  al., IEEE CG&A 1994); each round's data is the lines
//                  held, merged lines sent once;
//     pairwise     N regions by halving (CHOPIN, Ren and Lis, HPCA 2021);
//                  once a GPM has rendered everything it sends each other
//                  GPM its region, in N-1 rounds (round k: to g + k mod N),
//                  a GPM sending to one and receiving from one at a time
//                  (CHOPIN's image composition scheduler, as a fixed
//                  rotation).
//   The last two run when the scheme closes a frame or a composition group
//   (close()): each GPM's rounds wait for its last unit of work.
#pragma once

#include <functional>
#include <map>
#include <span>

#include "oovr/core/config.h"
#include "oovr/schemes/composition_spec.h"
#include "oovr/schemes/frame_sim.h"

namespace oovr {

// Framebuffers of a sort-last scheme: 0 is the final frame, 1 + g GPM g's
// own; build the FrameSim with sort_last_framebuffers(gpms).
inline int sort_last_framebuffers(int gpms) { return gpms + 1; }

// The owner of every tile when `parts` GPMs split a tiles_x x tiles_y
// screen by halving its longer side (in tiles) until each has one part;
// with an odd count the first part gets the smaller share. Indexed
// ty * tiles_x + tx.
std::vector<int> bisected_owners(int tiles_x, int tiles_y, int parts);

class Composer {
 public:
  // The scheme's own owners (per-eye, a Python scheme): `owner(tile_x,
  // tile_y)` is the GPM owning a screen tile's pixels, sent to it as each
  // piece of work ends.
  Composer(FrameSim& sim, CompositionSpec spec, std::function<int(int tile_x, int tile_y)> owner);
  // An algorithm: sort_last.composition, or `fallback` when it is "scheme"
  // (the scheme's registration must name the sort_last section).
  Composer(FrameSim& sim, CompositionSpec spec, CompositionAlgorithm fallback);

  CompositionAlgorithm algorithm() const { return m_algorithm; }
  // Whether pixels wait for close() (binary swap, pairwise).
  bool deferred() const;

  // Sets where `job`'s records write: pixels its GPM owns into the final
  // frame, the others into its own buffer; depth with them when the payload
  // has depth, else in the final frame's depth buffer.
  void target(FrameSim::TileJob& job) const;
  // After `unit` (the job's work): sends the job's pixels owned elsewhere to
  // their owners (a transfer each, category composition) and has the
  // owners' ROPs merge them; a deferred algorithm holds them for close().
  void send(const FrameSim::TileJob& job, int unit);
  // Ends a frame or a composition group: a deferred algorithm's rounds,
  // each GPM's starting after its pipeline's last unit so far. Returns the
  // composition units (transfers and merges) added since the last close,
  // whatever the algorithm: what must end before the group is composed.
  std::vector<int> close();

  // Bytes and pixels one record sends to its owner when it is rendered
  // elsewhere.
  uint64_t bytes(const TileWork& r) const;
  uint64_t pixels(const TileWork& r) const;
  // The GPM owning a record's pixels.
  int owner_of(const TileWork& r) const { return owner(r); }
  // What rendering `r` on `gpm` puts on the links, 0 when `gpm` owns its
  // pixels: its colour sent to the owner, and with a colour-only payload
  // the depth test's reads and writes in the owner's depth buffer, counted
  // as two more of its lines (an estimate: the test reads the lines it
  // covers, which may be more).
  uint64_t remote_bytes(const TileWork& r, int gpm) const { return owner(r) == gpm ? 0 : bytes(r) * (m_spec.depth ? 1 : 3); }

 private:
  // What a GPM holds of one tile it does not own, written by itself or
  // merged from others: the colour lines, the passed fragments (capped at
  // the tile's pixels) and the records not yet in the final frame.
  struct Held {
    uint32_t lines = 0;
    uint64_t passed = 0;
    std::vector<const TileWork*> records;
    void add(uint32_t more_lines, uint64_t more_passed, std::span<const TileWork* const> more, uint64_t tile_pixels);
  };
  using HeldTiles = std::map<uint32_t, Held>;  // by ty * tiles_x + tx

  void place_final_frame();
  int owner(const TileWork& r) const { return m_owner(r.tile_x, r.tile_y); }
  // Pixels and bytes sent for `lines` written and `passed` fragments (a
  // record's, or what a GPM holds of a tile).
  uint64_t pixels(uint32_t lines, uint64_t passed) const;
  uint64_t bytes(uint32_t lines, uint64_t passed) const;
  int owner_of_tile(uint32_t tile) const;  // tile = ty * tiles_x + tx
  uint64_t tile_pixels() const;
  // Moves `tiles` from GPM `from` to GPM `to`: a transfer after `after`,
  // then `to`'s ROPs merge them after the transfer and `merge_after`;
  // records reaching their owner are composed. Returns {transfer, merge}
  // units, or {-1, -1} when there was nothing to send.
  std::pair<int, int> move(int from, int to, HeldTiles tiles, std::vector<int> after, std::vector<int> merge_after);
  // The tiles GPM `gpm` holds whose owner `pick` chooses, removed from it.
  HeldTiles take(int gpm, const std::function<bool(int owner)>& pick);
  void binary_swap(const std::vector<int>& ready);
  void pairwise(const std::vector<int>& ready);

  FrameSim& m_sim;
  CompositionSpec m_spec;
  CompositionAlgorithm m_algorithm;
  std::function<int(int, int)> m_owner;
  std::vector<HeldTiles> m_held;  // per GPM (deferred algorithms)
  std::vector<int> m_units;       // composition units since the last close
};

}  // namespace oovr
