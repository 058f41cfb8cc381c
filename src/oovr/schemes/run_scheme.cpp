// Running a scheme (by name or as a SchemeRef), on one frame or over a window of frames in
// sequence (i_scheme.h).
#include <algorithm>
#include <cstdint>
#include <new>
#include <set>

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/memory_tape.h"
#include "oovr/schemes/window_run.h"

namespace oovr {

SchemeRef find_scheme(const std::string& name) {
  const SchemeFactory* f = Schemes::find(name);
  if (!f) {
    std::string names;
    for (const auto& n : Schemes::names()) names += (names.empty() ? "" : ", ") + n;
    throw Error("unknown scheme '" + name + "' (schemes: " + names + ")");
  }
  return {name, f->make()};
}

std::vector<std::string> schemes_in_order() {
  std::vector<std::string> names = Schemes::names();
  std::stable_sort(names.begin(), names.end(),
                   [](const std::string& a, const std::string& b) { return Schemes::find(a)->order < Schemes::find(b)->order; });
  return names;
}

bool scheme_reads_key(const std::string& scheme, const std::string& key) {
  const std::string section = config_section_of(key);
  const ConfigSection* s = section.empty() ? nullptr : ConfigSections::find(section);
  if (!s || !s->scheme_section) return true;
  const SchemeFactory* f = Schemes::find(scheme);
  return f && std::find(f->sections.begin(), f->sections.end(), section) != f->sections.end();
}

std::map<std::string, Config::Entry> scheme_entries(const std::string& scheme,
                                                    const std::map<std::string, Config::Entry>& entries) {
  std::map<std::string, Config::Entry> out;
  for (const auto& [key, e] : entries)
    if (scheme_reads_key(scheme, key)) out.emplace(key, e);
  return out;
}

namespace {

// The machine as `scheme` runs it: `spec` after its configure(), whose
// overrides name it as their source in the results.
std::shared_ptr<const MachineSpec> configured(const SchemeRef& scheme, const MachineSpec& spec) {
  auto c = std::make_shared<MachineSpec>(spec);
  c->set_source("scheme " + scheme.name);
  scheme.impl->configure(*c);
  return c;
}

SchemeResult run_configured(const SchemeRef& scheme, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                            std::shared_ptr<const MachineSpec> spec, std::shared_ptr<CarriedState> carried) {
  SchemeInput in;
  in.scene = &scene;
  in.frames = frames;
  in.spec = std::move(spec);
  in.carried = std::move(carried);
  SchemeResult r = scheme.impl->run(in);
  // Every run's conservation laws are checked by FrameSim::finish; a result
  // made some other way could hide a scheme that does no work.
  if (FrameSim::law_checks() && !r.laws_checked)
    throw Error("scheme '" + scheme.name +
                "' returned a result that FrameSim::finish did not make, so its conservation laws were not checked");
  return r;
}

}  // namespace

int scheme_frames_needed(const SchemeRef& scheme, const MachineSpec& spec) {
  return scheme.impl->frames_needed(configured(scheme, spec)->memory.gpms);
}

int scheme_frames_needed(const SchemeRef& scheme, const Config& config) {
  return scheme_frames_needed(scheme, MachineSpec::from_config(config));
}

int scheme_frames_needed(const std::string& name, const Config& config) {
  return Schemes::find(name) ? scheme_frames_needed(find_scheme(name), config) : 1;
}

void check_scheme_config(const SchemeRef& scheme, const MachineSpec& spec) { FrameSim::check(*configured(scheme, spec)); }

void check_scheme_config(const SchemeRef& scheme, const Config& config) {
  check_scheme_config(scheme, MachineSpec::from_config(config));
}

void check_scheme_config(const std::string& name, const Config& config) { check_scheme_config(find_scheme(name), config); }

SchemeResult run_scheme(const SchemeRef& scheme, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const MachineSpec& spec, std::shared_ptr<CarriedState> carried) {
  return run_configured(scheme, scene, frames, configured(scheme, spec), std::move(carried));
}

SchemeResult run_scheme(const SchemeRef& scheme, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const Config& config, std::shared_ptr<CarriedState> carried) {
  return run_scheme(scheme, scene, frames, MachineSpec::from_config(config), std::move(carried));
}

SchemeResult run_scheme(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const Config& config, std::shared_ptr<CarriedState> carried) {
  return run_scheme(find_scheme(name), scene, frames, config, std::move(carried));
}

SchemeResult run_scheme_window(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                               const Config& config, int window, std::vector<SchemeResult>* runs) {
  return run_scheme_window(name, scene, FramesInMemory(frames), config, window, runs);
}

SchemeResult run_scheme_window(const std::string& name, const Scene& scene, const FrameSequence& frames, const Config& config,
                               int window, std::vector<SchemeResult>* runs) {
  return run_scheme_window(find_scheme(name), scene, frames, config, window, runs);
}

SchemeResult run_scheme_window(const SchemeRef& scheme, const Scene& scene, const FrameSequence& frames, const Config& config,
                               int window, std::vector<SchemeResult>* runs) {
  return run_scheme_window(scheme, scene, frames, MachineSpec::from_config(config), window, runs);
}

namespace {

// The window's result from its measured runs, in order: the frames'
// latencies and timelines one after the other, counts per frame.
SchemeResult summarise(const std::vector<SchemeResult>& all, int window) {
  SchemeResult s = all.front();
  s.frame_latencies_s.clear();
  double time = 0;  // seconds the window's frames take, frames in flight overlapping
  for (auto& x : s.inter_gpm_bytes) x = 0;
  s.local_dram_bytes = s.covered_fragments = s.vertices = s.draws = s.units = 0;
  std::vector<double> busy(s.gpm_busy_s.size(), 0);
  // The frames' timelines one after the other, each at its frame's start
  // (with frames in flight, the group's frames share one timeline).
  s.timeline.clear();
  s.marks.clear();
  double offset = 0;
  for (size_t k = 0; k < all.size(); ++k) {
    for (TimelineUnit u : all[k].timeline) {
      u.frame = int(k);
      u.offset = offset;
      s.timeline.push_back(u);
    }
    for (TimelineMark mark : all[k].marks) {
      mark.frame = int(k);
      mark.offset = offset;
      s.marks.push_back(std::move(mark));
    }
    offset += all[k].frame_latency_s;
  }
  for (const SchemeResult& r : all) {
    s.frame_latencies_s.insert(s.frame_latencies_s.end(), r.frame_latencies_s.begin(), r.frame_latencies_s.end());
    time += double(r.frames_in_flight) / r.throughput_fps;
    for (size_t c = 0; c < s.inter_gpm_bytes.size(); ++c) s.inter_gpm_bytes[c] += r.inter_gpm_bytes[c];
    s.local_dram_bytes += r.local_dram_bytes;
    s.covered_fragments += r.covered_fragments;
    s.vertices += r.vertices;
    s.draws += r.draws;
    s.units += r.units;
    s.footprint_bytes = std::max(s.footprint_bytes, r.footprint_bytes);
    for (size_t g = 0; g < busy.size(); ++g) busy[g] += r.gpm_busy_s[g] / double(all.size());
  }
  // Per frame: bytes summed over the window's frames, divided by them.
  const auto per_frame = [&](uint64_t v) { return (v + uint64_t(window) / 2) / uint64_t(window); };
  for (auto& x : s.inter_gpm_bytes) x = per_frame(x);
  s.local_dram_bytes = per_frame(s.local_dram_bytes);
  s.gpm_busy_s = busy;
  // Every statistic by its rule (core/stats.h): counts per frame, the
  // scheme's figures the mean over the runs that report them.
  std::vector<const Stats*> stats;
  for (const SchemeResult& r : all) stats.push_back(&r.stats);
  s.stats = Stats::window(stats, uint64_t(window));
  double sum = 0;
  for (double l : s.frame_latencies_s) sum += l;
  s.frame_latency_s = sum / double(s.frame_latencies_s.size());
  s.throughput_fps = double(window) / time;
  return s;
}

}  // namespace

bool timing_only_key(const std::string& key) {
  // The timing section's keys (timing/gpm_model.cpp) but the set-up
  // triangles' bytes, which the links carry; the bandwidths and latencies
  // of the memory section, which only the timing reads.
  static const std::set<std::string> keys{"frequency",
                                          "gpm.lanes",
                                          "gpm.texture_units",
                                          "gpm.rops",
                                          "gpm.rop_pixels_per_clock",
                                          "gpm.raster_fragments_per_clock",
                                          "gpm.setup_triangles_per_clock",
                                          "gpm.requests_in_flight",
                                          "gpm.draw_cycles",
                                          "gpm.draws_ahead",
                                          "shader.vertex_instructions",
                                          "shader.fragment_instructions",
                                          "timing.sharing",
                                          "link.bandwidth",
                                          "link.latency",
                                          "dram.bandwidth",
                                          "dram.latency",
                                          "cache.l1.latency",
                                          "cache.l2.latency",
                                          "cache.remote.latency"};
  return keys.count(key) > 0;
}

std::string shared_replay_key(const SchemeRef& scheme, const MachineSpec& spec) {
  const SchemeFactory* f = Schemes::find(scheme.name);
  // A scheme outside the registry (Python) is keyed by its object: runs of
  // the same object only.
  std::string key = f ? (f->replays_as.empty() ? scheme.name : f->replays_as)
                      : "@" + std::to_string(reinterpret_cast<uintptr_t>(scheme.impl.get()));
  const std::shared_ptr<const MachineSpec> machine = configured(scheme, spec);
  for (const auto& [k, e] : machine->entries)
    if (!timing_only_key(k) && !k.starts_with("composition.")) key += "\n" + k + "=" + e.value;
  return key;
}

struct WindowRun::State {
  SchemeRef scheme;
  const Scene& scene;
  const FrameSequence& frames;
  std::shared_ptr<const MachineSpec> machine;  // configured once for the window's runs
  int window = 0;
  size_t groups = 0;  // of m frames, m the scheme's frames in flight
  size_t m = 1;
  SharedReplay* share = nullptr;
  enum class Mode { full, recording, playing } mode = Mode::full;
  std::shared_ptr<MemoryTape> recording;
  std::shared_ptr<MemoryTape::Player> player;
  std::shared_ptr<CarriedState> carried;  // made by the first step
  size_t next = 0;                        // steps taken: the warm-up's groups, then the measured pass's
  std::vector<SchemeResult> all;          // the measured pass's runs
  bool failed = false;                    // a step threw: the memory system is half way through it
  bool taken = false;                     // result() has moved the runs out

  State(SchemeRef s, const Scene& sc, const FrameSequence& f) : scheme(std::move(s)), scene(sc), frames(f) {}

  // Group i's frames, held only while it runs.
  SchemeResult run_group(size_t i) {
    std::vector<std::shared_ptr<const FrameTrace>> held;
    std::vector<const FrameTrace*> group;
    for (size_t k = 0; k < m; ++k) {
      held.push_back(frames.at(i * m + k));
      group.push_back(held.back().get());
    }
    return run_configured(scheme, scene, group, machine, carried);
  }

  void start() {
    carried = std::make_shared<CarriedState>();
    if (mode == Mode::recording) carried->recording = recording;
    if (mode == Mode::playing) {
      player = std::make_shared<MemoryTape::Player>(share->tape);
      carried->playing = player;
    }
    all.clear();
  }

  // Starts the run again without the tape: its calls differed from it.
  void in_full(const std::string& why) {
    share->use = SharedReplay::Use::mismatched;
    share->why = why;
    mode = Mode::full;
    player.reset();
    carried.reset();
    all.clear();
    next = 0;
  }
};

WindowRun::WindowRun(SchemeRef scheme, const Scene& scene, const FrameSequence& frames, const MachineSpec& spec, int window,
                     SharedReplay* share)
    : m(std::make_unique<State>(std::move(scheme), scene, frames)) {
  const std::string& name = m->scheme.name;
  m->machine = configured(m->scheme, spec);
  const int in_flight = m->scheme.impl->frames_needed(m->machine->memory.gpms);
  if (window < 1 || window % in_flight != 0)
    throw Error(name + " renders " + std::to_string(in_flight) + " frames at once (one per GPM): the number of frames (" +
                std::to_string(window) + ") must be a multiple of " + std::to_string(in_flight));
  if (int(frames.size()) < window)
    throw Error("not enough frames of trace: " + std::to_string(window) + " needed, " + std::to_string(frames.size()) + " given");
  m->window = window;
  m->m = size_t(in_flight);
  m->groups = size_t(window / in_flight);
  m->share = share;
  if (!share) return;
  const std::string key = shared_replay_key(m->scheme, spec);
  if (!share->tape) {
    m->mode = State::Mode::recording;
    m->recording = std::make_shared<MemoryTape>(key);
  } else if (share->tape->key() != key) {
    share->use = SharedReplay::Use::mismatched;
    share->why = "the tape was recorded for another scheme or memory system";
  } else {
    m->mode = State::Mode::playing;
  }
}

WindowRun::~WindowRun() = default;

bool WindowRun::done() const { return m->next == 2 * m->groups; }

size_t WindowRun::steps_left() const { return 2 * m->groups - m->next; }

void WindowRun::step() {
  State& s = *m;
  if (s.failed) throw Error("the run of " + s.scheme.name + " failed: it has no step left");
  if (done()) throw Error("the run of " + s.scheme.name + " has no step left");
  // A step that throws (but for a played run's difference from its tape,
  // which starts it again) leaves the run failed, not to go on from a
  // memory system half way through a frame.
  s.failed = true;
  // In sequence on one memory system, after an unmeasured warm-up pass over
  // the same frames: data is then where a game running these views would
  // have it (pre-allocated copies included), and the distribution engine's
  // rates are fitted.
  try {
    if (s.next == 0) s.start();
    SchemeResult r = s.run_group(s.next % s.groups);
    if (s.next >= s.groups) s.all.push_back(std::move(r));
    ++s.next;
    if (s.mode == State::Mode::playing && done() && !s.player->at_end())
      throw TapeMismatch("the run made fewer memory calls than the recording");
  } catch (const TapeMismatch& mismatch) {
    if (s.mode != State::Mode::playing) throw;
    s.in_full(mismatch.what());
    s.failed = false;
    return;
  } catch (const std::bad_alloc&) {
    throw Error(out_of_memory_message("simulating " + s.scheme.name + " on " + s.scene.name + " (" + std::to_string(s.window) +
                                      " frames)"));
  }
  s.failed = false;
  if (!done()) return;
  s.carried.reset();
  if (s.mode == State::Mode::recording) {
    s.share->tape = std::move(s.recording);
    s.share->use = SharedReplay::Use::recorded;
  } else if (s.mode == State::Mode::playing) {
    s.share->use = SharedReplay::Use::played;
    s.player.reset();
  }
}

SchemeResult WindowRun::result(std::vector<SchemeResult>* runs) {
  if (!done()) throw Error("the run of " + m->scheme.name + " is not done");
  if (m->taken) throw Error("the result of the run of " + m->scheme.name + " was taken already");
  m->taken = true;
  SchemeResult s = summarise(m->all, m->window);
  if (runs) *runs = std::move(m->all);
  return s;
}

SchemeResult run_scheme_window(const SchemeRef& scheme, const Scene& scene, const FrameSequence& frames, const MachineSpec& spec,
                               int window, std::vector<SchemeResult>* runs, SharedReplay* share) {
  WindowRun run(scheme, scene, frames, spec, window, share);
  while (!run.done()) run.step();
  return run.result(runs);
}

}  // namespace oovr
