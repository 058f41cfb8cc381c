// The GPM resource model: what a GPM can do per cycle (the paper's Table 1)
// and how a piece of rendering work becomes demands on those resources and
// on the memory system's DRAMs and links.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/memory/memory_system.h"
#include "oovr/timing/engine.h"
#include "oovr/timing/sharing.h"

namespace oovr {

struct TimingSpec {
  Hertz frequency{1e9};                 // Table 1: 1 GHz
  int lanes_per_sm = 64;                // Table 1: 64 shader cores per SM
  int texture_units_per_sm = 4;         // Table 1: 4 texture units per SM
  int rops = 8;                         // Table 1: 8 ROPs per GPM
  int rop_pixels_per_clock = 4;         // Section 3: each ROP outputs 4 pixels per cycle
  int raster_fragments_per_clock = 32;  // per GPM (assumed: two raster engines of 16)
  int setup_triangles_per_clock = 2;    // per GPM (assumed: one per raster engine)
  int vertex_instructions = 32;         // per vertex (assumed)
  // Per fragment lane; 0 = each draw's own, from what its pass samples and
  // computes (pipeline/shader_cost.h). A positive value overrides them all.
  int fragment_instructions = 0;
  int triangle_bytes = 96;  // a set-up triangle sent to another GPM (3 x 32 B, assumed)
  // Reads a GPM keeps outstanding, per SM (Little's law: at most this many
  // per latency); 0 for no limit. Accel-Sim's TITAN X (Pascal) texture
  // cache has 128 miss entries.
  int requests_in_flight = 128;
  // Front-end cycles per draw a GPM receives (command processing, state,
  // bindings), before any of its vertices; calibrated against a real GPU
  // (docs/validation.md).
  double draw_cycles = 625;
  // Draws a GPM's front end may run ahead of its pipeline: it receives draw
  // i once draw i - draws_ahead has ended (its command FIFO; assumed).
  int draws_ahead = 64;
  Sharing sharing = Sharing::fair;  // how running units share resources (timing/sharing.h)

  // Fragment lane instructions of `quads` 2x2 quads whose passes' own
  // instructions come to `own` (4 lanes a quad): `own`, unless
  // fragment_instructions overrides every pass.
  double fragment_work(uint64_t quads, uint64_t own) const {
    return fragment_instructions > 0 ? double(quads) * 4.0 * fragment_instructions : double(own);
  }

  static TimingSpec from_config(const Config& c);
};

// Rendering work of one unit, as counts.
struct WorkCounts {
  uint64_t vertices = 0;   // vertex shader invocations
  uint64_t triangles = 0;  // triangles set up (per eye they are projected into)
  uint64_t covered = 0;    // fragments rasterised (and depth-tested)
  uint64_t quads = 0;      // 2x2 quads shaded
  // Fragment lane instructions of those quads (4 lanes a quad, each the
  // instructions of its draw's pass).
  uint64_t fragment_instructions = 0;
  uint64_t samples = 0;   // bilinear texture lookups
  uint64_t passed = 0;    // fragments written by the ROPs
  uint64_t composed = 0;  // pixels merged by composition on the ROPs
};

// The machine's resources in a TimingEngine: per GPM shader lanes, texture
// units, raster (fragments), setup (triangles), ROPs, request slots (reads
// in flight) and its DRAM, and every link of the topology.
class MachineModel {
 public:
  MachineModel(const TimingSpec& timing, const MemorySpec& memory, const Topology& topology, TimingEngine& engine);
  // Demands of a unit on GPM `gpm` doing `w`, whose memory traffic was `t`.
  std::vector<std::pair<int, double>> demand(int gpm, const WorkCounts& w, const UnitTraffic& t) const;
  // Demands of moving `t`'s link bytes only (a transfer unit).
  std::vector<std::pair<int, double>> transfer_demand(const UnitTraffic& t) const;
  int queue(int gpm) const { return m_queue[size_t(gpm)]; }
  // The GPM's front end, which receives draws in order, beside its pipeline.
  int front_queue(int gpm) const { return m_front_queue[size_t(gpm)]; }
  // Seconds of front-end time for `draws` draws.
  double draw_seconds(double draws) const { return draws * m_timing.draw_cycles / m_timing.frequency.value; }
  // Request-seconds a unit's reads hold outstanding: each read for its
  // latency where it was served (MemorySpec's latencies; a remote read
  // pays the link hops both ways).
  double read_latency(const UnitTraffic& t) const;
  const TimingSpec& timing() const { return m_timing; }
  double cycles(double seconds) const { return seconds * m_timing.frequency.value; }

 private:
  TimingSpec m_timing;
  MemorySpec m_memory;
  struct Gpm {
    int shader, texture, raster, setup, rop, dram;
    int requests = -1;  // request slots (requests in flight), -1 without a limit
  };
  std::vector<Gpm> m_gpm;
  std::vector<int> m_link;
  std::vector<int> m_queue, m_front_queue;
};

}  // namespace oovr
