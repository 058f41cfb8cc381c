// The frame's conservation laws, checked after every run of every scheme
// (C++, Python or a user's file), so that a wrong policy is an error, not a
// speed-up (docs/model.md, "Schemes checked as they run"). FrameSim keeps a
// ledger of what the scheme did and checks it when the run finishes:
//
//   draws      every piece of a draw's work (its geometry, its tile
//              records) runs on a GPM under a draw that GPM's front end
//              received for that object: no work without its front-end
//              cost, no two objects' work under one draw;
//   fragments  every tile record of the frames that complete (frames[0 ..
//              frames_in_flight-1]) with covered fragments is rasterised
//              exactly once (a scheme that renders some records more than
//              once declares how often: FrameSim::declare_repeats), and
//              no record of another frame is;
//   pixels     every record's written pixels reach its frame's final
//              framebuffer exactly once: written there directly, or
//              written into a private buffer and composed (merged by the
//              owner's ROPs) once. Framebuffer k < frames_in_flight is
//              frame k's final one (0 for one frame in flight; AFR's GPM g
//              renders frame g into buffer g); the others are private.
//
// A violation is an Error naming the scheme, the law and the first object
// or tile that breaks it. The ledger costs a few bytes per record and a few
// operations per record replayed (measured in docs/performance.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/pipeline/frame_trace.h"

namespace oovr {

class RunLedger {
 public:
  explicit RunLedger(std::vector<const FrameTrace*> frames);

  // A record may be rasterised up to `times` times (at least 1).
  void allow_repeats(int times);
  int repeats_allowed() const { return m_repeats; }

  // GPM `gpm`'s front end received a draw (the command unit `unit`).
  void received(int unit);
  // Work on `object` ran on GPM `gpm` under its current draw `draw` (-1:
  // none). `what` names the work for a message ("geometry", "tile work").
  void work(int gpm, int draw, uint32_t object, const char* what);
  // Record `r` of `frame` was rasterised on GPM `gpm` under draw `draw`,
  // its colour written into framebuffer `colour_fb`.
  void rasterised(const FrameTrace& frame, const TileWork& r, int gpm, int draw, int colour_fb);
  // Record `r` (of one of the run's frames) had its pixels merged into the
  // final frame.
  void composed(const TileWork& r);

  // Throws Error naming `scheme`, the first law broken and where, when the
  // run broke one; `frames_in_flight` frames completed.
  void check(const std::string& scheme, int frames_in_flight) const;

 private:
  struct Where {
    int frame = -1;
    size_t record = 0;
  };
  // The frame and index of a record; frame -1 when it is of no frame of
  // the run.
  Where find(const TileWork& r) const;
  static std::string describe(const TileWork& r);

  std::vector<const FrameTrace*> m_frames;
  int m_repeats = 1;
  // Per command unit (indexed by unit id): the object its draw was
  // received for, once work ran under it; -1 before, -2 not a draw.
  std::vector<int64_t> m_draw_object;
  // Per frame and record: times rasterised (saturating), the colour
  // framebuffer of its first rasterisation (-1: none), times composed.
  std::vector<std::vector<uint16_t>> m_times;
  std::vector<std::vector<int16_t>> m_fb;
  std::vector<std::vector<uint16_t>> m_composed;
  // The first breach of the draws law seen as work was added, and how many;
  // the same for records replayed as part of a frame they are not of.
  std::string m_draw_breach, m_frame_breach;
  uint64_t m_draw_breaches = 0, m_frame_breaches = 0;
  // Records composed that belong to no frame of the run.
  uint64_t m_stray_composed = 0;
  // The index in m_frames of the frame rasterised() saw last (past the end:
  // none yet).
  size_t m_last_frame = ~size_t(0);
};

}  // namespace oovr
