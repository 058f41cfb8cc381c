// The machinery every scheme shares: a memory system and a timing engine
// for the configured machine, the scene laid out in memory, and ways to turn
// pieces of a FrameTrace into work units on GPMs. Units replay their memory
// accesses when they are added, so schemes add them in the order the GPMs
// would issue them (draw order, GPMs interleaved).
//
// What a GPM does for a draw, as units in its queue: its front end receives
// the draw (command(): per-draw cost), transforms its vertices (geometry()),
// then rasterises, shades and writes its tiles (tiles()). Data that moves
// between GPMs outside a unit's own memory accesses (set-up triangles handed
// over, composition, copies) is a transfer unit on the links, with the link
// latency of every hop.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "oovr/core/rng.h"
#include "oovr/memory/memory_system.h"
#include "oovr/schemes/conservation.h"
#include "oovr/schemes/i_scheme.h"
#include "oovr/schemes/memory_tape.h"
#include "oovr/timing/engine.h"
#include "oovr/timing/gpm_model.h"

namespace oovr {

struct CarriedState {
  std::shared_ptr<AddressMap> map;
  std::shared_ptr<SceneLayout> layout;
  std::shared_ptr<MemorySystem> memory;
  int framebuffers = 0;
  std::vector<uint32_t> colour, depth;  // framebuffer regions
  // Values a scheme keeps between frames (e.g. a predictor's fitted rates).
  std::map<std::string, std::vector<double>> values;
  // A memory replay shared with runs that differ only in timing
  // (schemes/memory_tape.h): the window's runs record their memory system's
  // answers on `recording`, or play `playing` back instead of having a
  // memory system (then `memory` stays null and `topology` is the links').
  // `calls`: the running hash of the window's memory calls.
  std::shared_ptr<MemoryTape> recording;
  std::shared_ptr<MemoryTape::Player> playing;
  std::shared_ptr<const Topology> topology;
  uint64_t calls = 0;
};

// Every method checks its arguments (GPMs, framebuffers, objects, frames,
// units to wait for) and throws Error naming the method, the argument and
// what exists: "command(gpm=4): GPM 4 does not exist (GPMs 0 to 3)". A
// scheme in C++ and one in Python (python/schemes.cpp) get the same checks.
class FrameSim {
 public:
  // `framebuffers`: colour + depth buffer pairs (one per GPM for schemes
  // that render into private buffers).
  FrameSim(const SchemeInput& in, int framebuffers = 1);
  // Throws the Error the constructor would for the machine `spec`.
  static void check(const MachineSpec& spec);

  int gpms() const { return m_memory_spec.gpms; }
  int sms() const { return m_memory_spec.sms_per_gpm; }
  // The memory system itself, for a scheme or a test that reads it
  // directly. Changing it through this would escape a shared replay's
  // checks: schemes change it through the methods here only. A run playing
  // a shared memory replay has none: it throws TapeMismatch, and the run is
  // made again in full.
  MemorySystem& memory();
  const SceneLayout& layout() const { return *m_layout; }
  const MachineModel& machine() const { return *m_machine; }
  const TimingSpec& timing() const { return m_timing_spec; }
  const Scene& scene() const { return *m_in.scene; }
  // The draws of a frame's trace (a captured game draws other objects in
  // each frame; other scenes the same ones): what its object indices name.
  const std::vector<Object>& draws(const FrameTrace& f) const { return scene().draws(f.frame); }
  // The machine (read once at the entry point; configured by the scheme).
  const MachineSpec& spec() const { return *m_in.spec; }
  const FrameTrace& frame(int k = 0) const { return *m_in.frames[size_t(k)]; }
  uint32_t colour(int fb) const { return m_colour[size_t(fb)]; }
  uint32_t depth(int fb) const { return m_depth[size_t(fb)]; }

  // GPM `gpm`'s front end receives `draws` draws: command processing, state
  // and bindings, gpm.draw_cycles each. The front end works beside the
  // pipeline, in draw order, at most gpm.draws_ahead draws ahead of it (it
  // waits for the end of the draw that many before). The draw becomes the
  // GPM's current one: pipeline units added on `gpm` from now on wait for
  // it. Every GPM that works on a draw receives it; a broadcast (baseline,
  // tile SFR) reaches every GPM.
  int command(int gpm, int draws = 1);
  // Pipeline units added on `gpm` from now on belong to the draw that
  // `command_unit` received (a runtime that sends draws ahead of the work).
  void use_draw(int gpm, int command_unit);
  // Vertex shading and triangle setup of `object` on `gpm`: its vertex and
  // index buffers are read; `vertex_passes` is 1 with SMP (both eyes share
  // the transform) and the number of eyes without; `triangles` is the number
  // set up (summed over the eyes projected into).
  // `frame_k`: which of the input's frames the object is drawn in (AFR's
  // frames in flight).
  int geometry(int gpm, uint32_t object, int vertex_passes, uint64_t triangles, std::vector<int> after = {}, int frame_k = 0);
  // Part of `object`'s geometry on `gpm` (GPUpd's cooperative projection,
  // the primitives a GPM received): the share [begin, end) of its vertices
  // (fractions, rounded to whole vertices), each running `vertex_cost` of
  // the vertex shader (1: all of it), reading that share of its vertex and
  // index buffers' lines; `triangles` set up.
  int geometry_part(int gpm, uint32_t object, double begin, double end, double vertex_cost, uint64_t triangles,
                    std::vector<int> after = {});
  // Rasterisation, shading, texturing and ROP work of `records` on `gpm`,
  // writing framebuffer pair `fb`; `incoming` bytes of set-up triangles
  // arrive from GPM `from` first (when from != gpm).
  int tiles(int gpm, std::span<const TileWork* const> records, int fb, const FrameTrace& frame, std::vector<int> after = {},
            int from = -1, uint64_t incoming = 0);
  // Several GPMs' tile work on one draw, which runs at the same time: the
  // memory accesses are replayed record by record in turn across the jobs
  // (the GPM starting each round rotates), so that first touch and the
  // home's L2 see the GPMs interleaved as they would be, not one GPM's whole
  // share before the next's. Returns the units, in job order.
  struct TileJob {
    int gpm;
    std::vector<const TileWork*> records;
    int fb = 0;
    std::vector<int> after;
    // Set-up triangles handed over from GPM `from` (a transfer unit the
    // job's unit waits for; nothing when from is -1 or the job's own GPM).
    int from = -1;
    uint64_t incoming = 0;
    // Per record, when records write different framebuffers: colour (else
    // fb) and depth (else as colour).
    std::vector<int> fbs = {};
    std::vector<int> depth_fbs = {};
  };
  std::vector<int> tiles_together(const std::vector<TileJob>& jobs, const FrameTrace& frame);
  // Moves `bytes` from one GPM to another: a unit on the links of the route,
  // with the link latency of every hop.
  int transfer(int from, int to, uint64_t bytes, Category c, std::vector<int> after = {});
  // The pre-allocation unit of `gpm` copies the pages of every region in
  // `regions` it does not hold yet into its DRAM (MemorySystem::preallocate,
  // one batch): a unit outside the GPM's pipeline, on the links and DRAMs.
  // Returns -1 when there was nothing to copy.
  int preallocate(int gpm, std::span<const uint32_t> regions, std::vector<int> after = {});
  // ROP work merging `pixels` on `gpm` (composition): the pixels that
  // `records` wrote into private buffers reach the final frame. It runs
  // beside the GPM's pipeline, not in its queue (the colour output stage
  // works asynchronously with shading, paper Section 5.3), sharing its ROPs
  // with whatever the GPM is rendering; it counts as busy time of the GPM.
  int compose(int gpm, std::span<const TileWork* const> records, uint64_t pixels, std::vector<int> after = {});
  // The scheme's own marks on the timeline, kept only when the machine asks
  // for one (MachineSpec::timeline; the calls cost nothing otherwise): a
  // span on `gpm` from unit `first`'s start to unit `last`'s finish, and an
  // instant at the current time of the run (from on_finish) or at 0.
  bool keeps_timeline() const { return m_in.spec->timeline; }
  void mark_span(std::string name, std::string category, int gpm, int first, int last,
                 std::vector<std::pair<std::string, double>> args = {});
  void mark_instant(std::string name, std::string category, int gpm, std::vector<std::pair<std::string, double>> args = {});
  // GPM `gpm`'s pipeline's last unit so far (-1: none yet): where work that
  // must follow everything the GPM was given starts (composition rounds).
  int last_unit(int gpm) const;
  // The memory system's copies made ahead of use (pre-allocation, Section
  // 5.2; MemorySystem::preallocate): pages dropped for room and refused for
  // want of it since the memory system was built, and the most bytes of
  // copies one GPM has held. A played run reads them from the tape.
  struct Copies {
    uint64_t evicted = 0, refused = 0, peak_bytes = 0;
  };
  Copies copies();
  // Makes `gpm` the home of the page holding `address` if nobody has
  // touched it yet (MemorySystem::place): a buffer the application maps
  // into a GPM's DRAM, as a sort-last scheme maps its final frame.
  void place(uint64_t address, int gpm);
  // The scheme renders some records up to `times` times by design (the
  // conservation check allows it; schemes/conservation.h).
  void declare_repeats(int times);
  // GPM `gpm` (-1: every GPM) finished a draw: call it after adding the
  // draw's units on that GPM. Its end bounds how far the front end runs
  // ahead, and it is the boundary at which `cache.remote.invalidate =
  // "draw"` drops the GPM's remote cache (MCM-GPU flushes its L1.5 at kernel
  // boundaries).
  void end_draw(int gpm = -1);

  // Runs the timing engine; fills the result's timing, traffic and memory
  // numbers. `frames_in_flight` frames complete in the makespan. Then
  // checks the frame's conservation laws (schemes/conservation.h): a run
  // that breaks one is an Error naming the scheme, the law and where.
  // `on_finish(unit)` is called as units end and may add units (a runtime
  // scheduler); engine() then answers questions about progress.
  SchemeResult finish(const std::string& scheme, int frames_in_flight = 1, const std::function<void(int unit)>& on_finish = {});
  const TimingEngine& engine() const { return m_engine; }

  // Whether runs check their conservation laws (on unless turned off):
  // for benchmarks that measure the simulation alone, never for results.
  static void set_law_checks(bool on);
  static bool law_checks();
  // Whether replays leave out a record's repeats in an L1 set (replay; on
  // unless turned off): for the tests that show it changes nothing.
  static void set_repeats_counted(bool on);

 private:
  int add(int gpm, const WorkCounts& w, const UnitTraffic& t, std::vector<int> after, TimelineUnit info, bool in_queue = true);
  // The geometry unit of geometry() and geometry_part(): `vertices` shaded,
  // `triangles` set up, reading bytes [begin, end) (shares) of the object's
  // vertex and index buffers.
  int geometry_unit(int gpm, uint32_t object, const Object& o, double begin, double end, uint64_t vertices, uint64_t triangles,
                    std::vector<int> after);
  // Argument checks (see the class comment); each returns what it checked.
  // The GPM's and framebuffer's are inline, their messages out of line:
  // they are made for every record of every job (as calls, 0.7% of a
  // sweep's instructions).
  int gpm_arg(int gpm, const char* fn, const char* param = "gpm") const {
    if (gpm < 0 || gpm >= gpms()) [[unlikely]]
      no_gpm(gpm, fn, param);
    return gpm;
  }
  int fb_arg(int fb, const char* fn, const char* param = "fb") const {
    if (fb < 0 || size_t(fb) >= m_colour.size()) [[unlikely]]
      no_fb(fb, fn, param);
    return fb;
  }
  [[noreturn]] void no_gpm(int gpm, const char* fn, const char* param) const;
  [[noreturn]] void no_fb(int fb, const char* fn, const char* param) const;
  int unit_arg(int unit, const char* fn, const char* param) const;
  const std::vector<int>& after_arg(const std::vector<int>& after, const char* fn) const;
  const FrameTrace& frame_arg(const FrameTrace& frame, const char* fn) const;
  const Object& object_arg(uint32_t object, const FrameTrace& frame, const char* fn) const;
  std::vector<int> tiles_checked(const std::vector<TileJob>& jobs, const FrameTrace& frame);
  // A unit of data movement (transfer, copy) outside every GPM's pipeline.
  int add_movement(std::vector<std::pair<int, double>> demand, std::vector<int> after, double latency, TimelineUnit info);
  // Replays one record's memory accesses on `gpm` into `total` and `w`.
  void replay(int gpm, const TileWork& r, int colour_fb, int depth_fb, const FrameTrace& frame, UnitTraffic& total,
              WorkCounts& w);
  UnitTraffic empty_traffic() const;
  const Topology& topology() const { return *m_topology; }
  // The memory calls' running hash (CarriedState::calls): every argument
  // that decides what the memory system answers is folded in, a call's tag
  // first; only a run that records or plays a tape keeps it.
  bool taped() const { return m_recording || m_playing; }
  void mix(std::initializer_list<uint64_t> xs) {
    if (taped())
      for (uint64_t x : xs) m_calls = mix64(m_calls ^ x);
  }
  // The memory system's answer to the call just mixed in: played back from
  // the tape, or asked of it by `ask` (which fills `t`, or returns the
  // value) and put on the tape when recording.
  template <class Ask>
  void answer_traffic(UnitTraffic& t, Ask&& ask) {
    if (m_playing) return m_playing->traffic(m_calls, t);
    ask();
    if (m_recording) m_recording->traffic(m_calls, t);
  }
  template <class Ask>
  uint64_t answer_value(Ask&& ask) {
    if (m_playing) return m_playing->value(m_calls);
    const uint64_t v = ask();
    if (m_recording) m_recording->value(m_calls, v);
    return v;
  }

  SchemeInput m_in;
  MemorySpec m_memory_spec;
  TimingSpec m_timing_spec;
  std::shared_ptr<AddressMap> m_map;
  std::shared_ptr<SceneLayout> m_layout;
  std::shared_ptr<MemorySystem> m_memory;      // null while playing a tape
  std::shared_ptr<const Topology> m_topology;  // the memory system's, or the played run's own
  MemoryTape* m_recording = nullptr;
  MemoryTape::Player* m_playing = nullptr;
  uint64_t m_calls = 0;                    // carried back at finish
  std::vector<UnitTraffic> m_job_traffic;  // tiles_checked()'s, kept between calls
  TrafficTotals m_before;                  // the memory system's totals when this frame began
  Stats m_stats_before;                    // and its statistics
  TimingEngine m_engine;
  std::unique_ptr<MachineModel> m_machine;
  std::vector<uint32_t> m_colour, m_depth;
  std::vector<int> m_last;  // per GPM: its pipeline's last unit, or -1
  // Per GPM: the current draw's command unit (-1: none), the pipeline's last
  // unit when each draw ended, and the draws received.
  std::vector<int> m_draw;
  std::vector<std::vector<int>> m_draw_ends;
  std::vector<size_t> m_draws_received;
  std::vector<int> m_unit_gpm;            // per unit: the GPM whose busy time it counts in, or -1
  std::vector<TimelineUnit> m_unit_info;  // per unit, with a timeline only: what it is (times filled by finish)
  struct PendingSpan {
    TimelineMark mark;
    int first, last;
  };
  std::vector<PendingSpan> m_spans;  // resolved by finish
  std::vector<TimelineMark> m_instants;
  std::vector<LineAccess> m_scratch;
  // The frame's texture lines less their L1 repeats (replay), kept for the
  // frame last replayed: the L1's sets (0, off, where they do not follow
  // the index) and its ways for the LRU rule (0: not LRU).
  uint64_t m_repeat_sets = 0;
  int m_repeat_lru_ways = 0;
  const FrameTrace* m_repeats_of = nullptr;
  std::shared_ptr<const TexLinesWithoutRepeats> m_repeats;
  const std::shared_ptr<const TexLinesWithoutRepeats>& without_repeats(const FrameTrace& frame);
  // (object, tile) -> GPM for frames[0], in replay order; finish() makes
  // SchemeResult::owner of it (a log, not a map: a record each, cheap).
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, int>> m_owner_log;
  std::unique_ptr<RunLedger> m_ledger;  // what the run did, for its laws (null: not checked)
  SchemeResult m_result;
};

// The tile records of one object, grouped by eye (in trace order).
struct ObjectRecords {
  std::vector<const TileWork*> eye[2];
  // Both eyes' records, the left eye's first (a multi-view draw's).
  std::vector<const TileWork*> both() const {
    std::vector<const TileWork*> all = eye[0];
    all.insert(all.end(), eye[1].begin(), eye[1].end());
    return all;
  }
};
std::vector<ObjectRecords> records_by_object(const FrameTrace& t, size_t objects);

}  // namespace oovr
