// Parallel-rendering schemes (DESIGN.md, "Schemes"): each replays the same
// FrameTrace through its own distribution of work over GPMs, placement of
// data and composition, on the memory system and timing model. One file per
// scheme in impl/, registered by name; schemes never include each other and
// share only the machinery beside this file: frame_sim.h (units on GPMs),
// sort_first.h (tile owners) and composition.h (sort-last composition).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "oovr/core/config.h"
#include "oovr/core/registry.h"
#include "oovr/core/stats.h"
#include "oovr/memory/memory_system.h"
#include "oovr/pipeline/frame_trace.h"
#include "oovr/scene/scene.h"
#include "oovr/schemes/machine_spec.h"

namespace oovr {

// What carries over from one frame to the next when a scheme renders frames
// in sequence (frame_sim.h defines it): the memory system, so that pages
// stay where first touch or pre-allocation put them, as a GPU's memory does
// between frames, and values a scheme learns at run time.
struct CarriedState;
class MemoryTape;

struct SchemeInput {
  const Scene* scene = nullptr;
  // Consecutive frames' traces; frames[0] is the frame simulated. Schemes
  // with frames in flight (AFR) use as many as they need.
  std::vector<const FrameTrace*> frames;
  // The machine, read once at the entry point, after the scheme's own
  // configure() (machine_spec.h).
  std::shared_ptr<const MachineSpec> spec;
  // Shared by the frames of one sequence (null: a frame on its own, cold).
  std::shared_ptr<CarriedState> carried;
};

// One unit of work as the timing engine ran it (MachineSpec::timeline):
// what it was, where, and when, in seconds from its frame's start.
struct TimelineUnit {
  enum class Kind : uint8_t { command, geometry, tiles, compose, transfer, prealloc };
  Kind kind = Kind::tiles;
  int frame = 0;                                // the window's frame (run_scheme_window), from 0
  int gpm = -1;                                 // the GPM working (a transfer: the receiver; a copy: the GPM copied to)
  int from = -1;                                // a transfer: the sender
  int object = -1;                              // geometry and tiles: the (first) object
  double start = 0, work_done = 0, finish = 0;  // work_done to finish: latency (memory, link hops)
  double offset = 0;                            // the frame's start in the window, seconds
};
const char* timeline_kind_name(TimelineUnit::Kind k);

// What a scheme says of its own work on the timeline (MachineSpec::timeline):
// a span over units (an OO-VR batch on its GPM) or an instant (a decision),
// with figures as arguments. Times as TimelineUnit's.
struct TimelineMark {
  std::string name, category;
  int frame = 0;
  int gpm = -1;
  double start = 0, finish = -1;  // finish < 0: an instant
  double offset = 0;
  std::vector<std::pair<std::string, double>> args;
};

struct SchemeResult {
  std::string scheme;
  int gpms = 0;
  double frequency_hz = 0;
  double frame_latency_s = 0;             // first command to last pixel composed, one frame (mean of frame_latencies_s)
  std::vector<double> frame_latencies_s;  // each frame's latency (several for frames in flight)
  double throughput_fps = 0;              // frames per second over the frames in flight
  int frames_in_flight = 1;
  std::vector<double> gpm_busy_s;
  PerCategory inter_gpm_bytes{};
  uint64_t local_dram_bytes = 0;  // bytes read and written by every DRAM
  uint64_t footprint_bytes = 0;   // memory resident in all GPMs' DRAMs
  // Counts summed over every GPM (and, from run_scheme_window, every frame):
  uint64_t covered_fragments = 0;  // fragments rasterised by all units (duplicates included)
  uint64_t vertices = 0;           // vertex shader invocations (duplicates included)
  uint64_t draws = 0;              // draws received by GPM front ends
  uint64_t units = 0;
  // Per screen tile of frames[0]: bytes moved between GPMs for its work.
  std::vector<uint64_t> tile_inter_gpm_bytes;
  // (object, tile index) -> GPM that shaded it, for frames[0]: sorted by
  // key, one entry a key (the last GPM that shaded it); owner_of finds one.
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, int>> owner;
  std::map<std::string, Config::Entry> config;  // resolved configuration, described (Config::entries)
  std::vector<std::string> notes;
  // Statistics (core/stats.h): the memory system's and the timing
  // engine's for this frame (FrameSim::finish), then the scheme's own
  // figures at its name (OO-VR's batches, moved chunks and predictor
  // rates: add_own). From run_scheme_window: merged by each one's rule.
  Stats stats;
  // Every unit, when the machine asked for it (MachineSpec::timeline); from
  // run_scheme_window, every measured frame's, one after the other.
  std::vector<TimelineUnit> timeline;
  std::vector<TimelineMark> marks;  // the scheme's spans and instants, with the timeline
  // Set by FrameSim::finish once the run's conservation laws held
  // (schemes/conservation.h); run_scheme refuses a result without it.
  bool laws_checked = false;

  // Adds one of the scheme's own figures (location: the scheme's name).
  void add_own(std::string name, double value, std::string unit = "", Merge merge = Merge::mean) {
    stats.add(scheme, std::move(name), value, std::move(unit), merge);
  }
  double frame_latency_cycles() const { return frame_latency_s * frequency_hz; }
  uint64_t total_inter_gpm_bytes() const;
  // The GPM that shaded `object` in tile `tile` of frames[0]; -1 when none did.
  int owner_of(uint32_t object, uint32_t tile) const;
  double best_to_worst() const;  // busiest GPM's busy time over the least busy one's
};

class Scheme {
 public:
  virtual ~Scheme() = default;
  // Frames of trace the scheme needs for `gpms` GPMs (AFR: one per GPM).
  virtual int frames_needed(int gpms) const {
    (void)gpms;
    return 1;
  }
  // Machine overrides this scheme makes (e.g. 1 TB/s links): it edits the
  // typed fields and records each with MachineSpec::set_entry. Applied
  // before frames_needed is asked.
  virtual void configure(MachineSpec& spec) const { (void)spec; }
  virtual SchemeResult run(const SchemeInput& in) const = 0;
};

struct SchemeFactory {
  std::string description;
  std::function<std::unique_ptr<Scheme>()> make;
  // Where the scheme stands in tables, plots and the default comparison
  // (schemes_in_order): the paper's schemes in the paper's order (10, 20,
  // ...), then the others, by name.
  int order = 1000;
  // The configuration sections of its own it reads (ConfigSection::
  // scheme_section, e.g. OO-VR's "oo"), besides the machine's.
  std::vector<std::string> sections = {};
  // The scheme whose distribution and placement this one's are, on a
  // machine that differs only in timing (baseline-1tb is the baseline with
  // faster links): their runs may share one memory replay
  // (SharedReplay). Empty: its own. A wrong claim costs time, never a
  // result: a played run whose calls differ is run again in full.
  std::string replays_as = {};
};
using Schemes = Registry<SchemeFactory>;

// Whether a run of `scheme` reads `key`: a key of a machine section, or of
// a section the scheme names (a scheme not registered, written in Python,
// reads the machine's). A key no section declares is the machine's (it is
// refused elsewhere).
bool scheme_reads_key(const std::string& scheme, const std::string& key);
// The entries of `entries` (Config::entries) that a run of `scheme` reads:
// what its result and its record list, and what its id hashes.
std::map<std::string, Config::Entry> scheme_entries(const std::string& scheme,
                                                    const std::map<std::string, Config::Entry>& entries);

// Every registered scheme, by order, then name: the one scheme order that
// `oovr compare`, the paper's document and the report read.
std::vector<std::string> schemes_in_order();

// A scheme to run and the name its results carry: a registered one
// (find_scheme), or one made outside the registry (a scheme written in
// Python, python/). Every function below taking a name looks it up and
// runs the SchemeRef.
struct SchemeRef {
  std::string name;
  std::shared_ptr<const Scheme> impl;
};
// The registered scheme `name`. Throws Error naming the registered ones
// when there is none.
SchemeRef find_scheme(const std::string& name);

// Runs a scheme on `frames` (rendered with the memory system's line size),
// continuing from `carried` when given. Throws Error for an unknown scheme.
// The machine is `spec` after the scheme's configure(); the overloads
// taking a Config read it first (an entry point's work).
SchemeResult run_scheme(const SchemeRef& scheme, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const MachineSpec& spec, std::shared_ptr<CarriedState> carried = nullptr);
SchemeResult run_scheme(const SchemeRef& scheme, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const Config& config, std::shared_ptr<CarriedState> carried = nullptr);
SchemeResult run_scheme(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const Config& config, std::shared_ptr<CarriedState> carried = nullptr);
// Frames of trace the scheme needs with this configuration (1 for unknown
// names: run_scheme reports those).
int scheme_frames_needed(const SchemeRef& scheme, const MachineSpec& spec);
int scheme_frames_needed(const SchemeRef& scheme, const Config& config);
int scheme_frames_needed(const std::string& name, const Config& config);
// Throws the Error a run of the scheme on this configuration would, before
// any trace is rendered: an unknown scheme, a bad key or value, a placement
// policy schemes cannot use.
void check_scheme_config(const SchemeRef& scheme, const MachineSpec& spec);
void check_scheme_config(const SchemeRef& scheme, const Config& config);
void check_scheme_config(const std::string& name, const Config& config);

// Consecutive frames' traces handed out one at a time, so that a long
// window need not be in memory at once (run/frames.h streams them
// from disk). at() is safe to call from several threads; the caller holds
// the trace while it uses it.
class FrameSequence {
 public:
  virtual ~FrameSequence() = default;
  virtual size_t size() const = 0;
  virtual std::shared_ptr<const FrameTrace> at(size_t k) const = 0;
};

// Traces already in memory, not owned.
class FramesInMemory final : public FrameSequence {
 public:
  explicit FramesInMemory(std::vector<const FrameTrace*> frames) : m_frames(std::move(frames)) {}
  size_t size() const override { return m_frames.size(); }
  std::shared_ptr<const FrameTrace> at(size_t k) const override {
    return std::shared_ptr<const FrameTrace>(std::shared_ptr<const FrameTrace>(), m_frames.at(k));  // aliasing: no ownership
  }

 private:
  std::vector<const FrameTrace*> m_frames;
};

// Runs `name` over the first `window` of `frames`: a scheme with m frames in
// flight (AFR: one per GPM) on each group of m frames, any other on each
// frame in turn, so that every scheme is measured on the same frames. The
// frames run in sequence on one memory system, after an unmeasured warm-up
// pass over the same frames: the measured frames see data where the frames
// before left it (the steady state of a running game), not a cold start.
// The summary has the mean frame latency, the throughput over the window,
// and per-frame means of traffic, DRAM bytes and GPM busy time; its
// per-tile traffic and owners are those of the first measured run
// (frames[0]). `runs`, when given, receives every run's own result. Throws
// Error when `window` is not a multiple of m or frames are missing.
// Only the frames of the group being run are held at a time.
//
// `share`, when given, shares the window's memory replay with other runs
// (schemes/memory_tape.h): with no tape, the run records one into it; with
// one (recorded by a run with the same shared_replay_key), the run plays it
// back instead of simulating the caches, and is run again in full if its
// calls differ from the recording's. Either way the result is what a run
// without `share` gives, bit for bit.
struct SharedReplay {
  std::shared_ptr<const MemoryTape> tape;
  enum class Use { none, recorded, played, mismatched } use = Use::none;
  std::string why;  // with mismatched: the first difference
};
SchemeResult run_scheme_window(const SchemeRef& scheme, const Scene& scene, const FrameSequence& frames, const MachineSpec& spec,
                               int window, std::vector<SchemeResult>* runs = nullptr, SharedReplay* share = nullptr);
// Runs that may share a memory replay have equal keys: the scheme's
// replays_as, and every key of the machine its run reads (after its
// configure()) but those that only set timing (timing_only_key) and the
// composition's (which schemes that compose check by their calls).
std::string shared_replay_key(const SchemeRef& scheme, const MachineSpec& spec);
// Whether a configuration key only sets timing: the memory system never
// sees it (bandwidths, latencies, the GPMs' clock and throughputs, the
// timing model's switches).
bool timing_only_key(const std::string& key);
SchemeResult run_scheme_window(const SchemeRef& scheme, const Scene& scene, const FrameSequence& frames, const Config& config,
                               int window, std::vector<SchemeResult>* runs = nullptr);
SchemeResult run_scheme_window(const std::string& name, const Scene& scene, const FrameSequence& frames, const Config& config,
                               int window, std::vector<SchemeResult>* runs = nullptr);
SchemeResult run_scheme_window(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                               const Config& config, int window, std::vector<SchemeResult>* runs = nullptr);

}  // namespace oovr
