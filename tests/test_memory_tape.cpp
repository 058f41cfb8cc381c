// One memory replay shared by runs that differ only in timing
// (schemes/memory_tape.h): a played run is the run, bit for bit; runs whose
// calls or memory systems differ are run in full; every timing key of the
// configuration is one the memory system never sees. And the replay's other
// shortcut: a record's repeats in an L1 set counted, not replayed
// (FrameSim::replay), change no run.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <set>

#include "oovr/core/config_sections.h"
#include "oovr/run/result_json.h"
#include "oovr/run/simulation.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/i_scheme.h"
#include "oovr/schemes/window_run.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& courtyard() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("courtyard", 320, 480, 30, 4);
  return *r;
}

// The four frames, one record of frame `k` writing other depth lines (its
// depth write mask inverted): the same records in the same order, so a
// scheme's calls are those on the frames as rendered but for their hash.
std::vector<FrameTrace> with_one_record_changed(size_t k) {
  std::vector<FrameTrace> changed;
  for (const FrameTrace* t : courtyard().traces) changed.push_back(*t);
  TileWork& w = changed.at(k).tiles[changed[k].tiles.size() / 2];
  w.depth_write_mask = ~w.depth_write_mask;
  return changed;
}

// oovr compare's simulation of four small courtyard frames, rendered for it.
SimulationRequest courtyard_simulation() {
  SimulationRequest r;
  r.scene = "courtyard";
  r.rig.eye_width = 160;
  r.rig.eye_height = 240;
  r.frame = 30;
  r.frames = 4;
  r.use_cache = false;
  return r;
}

// Everything a run says, its per-tile bytes and owners included.
std::string everything(const SchemeResult& r) {
  nlohmann::ordered_json j = to_json(r);
  j["tile_inter_gpm_bytes"] = r.tile_inter_gpm_bytes;
  nlohmann::ordered_json owners = nlohmann::ordered_json::array();
  for (const auto& [key, gpm] : r.owner) owners.push_back({key.first, key.second, gpm});
  j["owner"] = owners;
  return j.dump();
}

std::string everything(const SchemeResult& r, const std::vector<SchemeResult>& runs) {
  std::string s = everything(r);
  for (const SchemeResult& run : runs) s += "\n" + everything(run);
  return s;
}

// Equal, or where they first differ (the texts are long).
testing::AssertionResult same(const std::string& a, const std::string& b) {
  if (a == b) return testing::AssertionSuccess();
  size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  const size_t from = i < 80 ? 0 : i - 80;
  return testing::AssertionFailure() << "they differ at character " << i << ":\n  " << a.substr(from, 160) << "\n  "
                                     << b.substr(from, 160);
}

Config config_of(std::initializer_list<std::string> settings) {
  Config c;
  for (const std::string& s : settings) c.set(s);
  return c;
}

// The scheme over the four frames (one window, after its warm-up pass),
// sharing `share` when given: everything it says, and every run's.
std::string run(const std::string& scheme, const Config& c, SharedReplay* share = nullptr) {
  const test::RenderedFrames& r = courtyard();
  std::vector<SchemeResult> runs;
  const SchemeResult s =
      run_scheme_window(find_scheme(scheme), r.scene, FramesInMemory(r.traces), MachineSpec::from_config(c), 4, &runs, share);
  return everything(s, runs);
}

// A value other than the default for every key that only sets timing.
const std::map<std::string, std::string> kTimingValues{
    {"frequency", "1.4GHz"},
    {"gpm.lanes", "32"},
    {"gpm.texture_units", "2"},
    {"gpm.rops", "4"},
    {"gpm.rop_pixels_per_clock", "2"},
    {"gpm.raster_fragments_per_clock", "8"},
    {"gpm.setup_triangles_per_clock", "2"},
    {"gpm.requests_in_flight", "0"},
    {"gpm.draw_cycles", "0"},
    {"gpm.draws_ahead", "2"},
    {"shader.vertex_instructions", "40"},
    {"shader.fragment_instructions", "60"},
    {"timing.sharing", "equal"},
    {"link.bandwidth", "32GBps"},
    {"link.latency", "300ns"},
    {"dram.bandwidth", "400GBps"},
    {"dram.latency", "250ns"},
    {"cache.l1.latency", "40ns"},
    {"cache.l2.latency", "300ns"},
    {"cache.remote.latency", "120ns"},
};

TEST(MemoryTape, EveryTimingKeyIsOneTheMemorySystemNeverSees) {
  // The timing section's keys are timing-only, but the bytes of a set-up
  // triangle, which the links carry; the memory section's bandwidths and
  // latencies are too, and nothing else is.
  const ConfigSection* timing = ConfigSections::find("timing");
  ASSERT_NE(timing, nullptr);
  for (const ConfigKey& k : timing->keys) EXPECT_EQ(timing_only_key(k.key), k.key != "shader.triangle_bytes") << k.key;
  for (const auto& [key, value] : kTimingValues) EXPECT_TRUE(timing_only_key(key)) << key;
  for (const char* key : {"gpms", "gpm.sms", "link.topology", "cache.l1.size", "memory.placement", "link.energy_per_bit",
                          "shader.triangle_bytes", "composition.payload", "oo.predictor"})
    EXPECT_FALSE(timing_only_key(key)) << key;
}

TEST(MemoryTape, ARecordsRepeatsInItsL1AreCountedAsTheHitsTheyAre) {
  // Every scheme, with the repeats left out of its replays and with every
  // line replayed: the same run to the last byte, on Table 1's L1 (256 sets
  // of 4 ways, LRU), on one of 2 ways (512 sets), on a FIFO L1 (the LRU
  // rule does not apply), and with 16 KB pages, where the sets' span
  // (32 KB) is more than a page: textures' lines do not fall in the sets by
  // their index, and nothing may be left out.
  const test::RenderedFrames& r = courtyard();
  for (const auto& trace : r.traces) {
    const auto kept = trace->tex_lines_without_repeats(256);
    ASSERT_NE(kept, nullptr) << "courtyard's repeats are not the majority, so this test could not tell";
    EXPECT_LT(kept->lines.size() * 4, trace->tex_lines.size());
    const auto lru = trace->tex_lines_without_repeats(256, 4);
    ASSERT_NE(lru, nullptr);
    EXPECT_LT(lru->lines.size(), kept->lines.size());
  }
  for (const Config& c :
       {Config{}, config_of({"cache.l1.ways=2"}), config_of({"cache.l1.replacement=fifo"}), config_of({"memory.page=16KB"})})
    for (const std::string& scheme : Schemes::names()) {
      const std::string counted = run(scheme, c);
      FrameSim::set_repeats_counted(false);
      const std::string replayed = run(scheme, c);
      FrameSim::set_repeats_counted(true);
      EXPECT_TRUE(same(counted, replayed)) << scheme;
    }
}

TEST(MemoryTape, APlayedRunIsTheRunBitForBit) {
  // Every scheme, recorded on Table 1's machine, then on one whose every
  // timing key differs: played back (or, where its calls differ, run in
  // full), it says what the run without a tape says, to the last byte.
  std::vector<std::string> settings;
  for (const auto& [key, value] : kTimingValues) settings.push_back(key + "=" + value);
  Config other;
  for (const std::string& s : settings) other.set(s);
  std::set<std::string> played;
  for (const std::string& scheme : Schemes::names()) {
    SharedReplay share;
    const std::string recorded = run(scheme, Config{}, &share);
    ASSERT_EQ(share.use, SharedReplay::Use::recorded) << scheme;
    ASSERT_TRUE(share.tape) << scheme;
    EXPECT_TRUE(same(recorded, run(scheme, Config{}))) << scheme << ": recording changed the run";
    // On its own machine every scheme's calls are the recording's.
    SharedReplay played_here = share;
    EXPECT_TRUE(same(run(scheme, Config{}, &played_here), recorded)) << scheme;
    EXPECT_EQ(played_here.use, SharedReplay::Use::played) << scheme << ": " << played_here.why;
    const std::string full = run(scheme, other);
    ASSERT_FALSE(same(full, recorded)) << scheme << ": the timing keys changed nothing, so this test could not tell";
    EXPECT_TRUE(same(run(scheme, other, &share), full)) << scheme << " (" << share.why << ")";
    if (share.use == SharedReplay::Use::played) played.insert(scheme);
    else EXPECT_EQ(share.use, SharedReplay::Use::mismatched) << scheme;
  }
  // The schemes whose distribution does not follow the timing play back;
  // OO-VR's runtime does, and reads the memory system's copies.
  for (const char* scheme : {"baseline", "baseline-paged", "afr", "sfr-v", "sfr-h", "object", "single-gpm", "two-pass", "ideal"})
    EXPECT_TRUE(played.count(scheme)) << scheme;
  EXPECT_FALSE(played.count("oo-vr"));
}

TEST(MemoryTape, EachTimingKeyAloneIsPlayedBack) {
  SharedReplay share;
  (void)run("baseline", Config{}, &share);
  for (const auto& [key, value] : kTimingValues) {
    const Config c = config_of({key + "=" + value});
    SharedReplay s = share;
    EXPECT_TRUE(same(run("baseline", c, &s), run("baseline", c))) << key;
    EXPECT_EQ(s.use, SharedReplay::Use::played) << key << ": " << s.why;
  }
}

TEST(MemoryTape, TheBaselineWithFasterLinksPlaysTheBaselines) {
  // baseline-1tb replays as the baseline (SchemeFactory::replays_as).
  const MachineSpec table1 = MachineSpec::from_config(Config{});
  EXPECT_EQ(shared_replay_key(find_scheme("baseline"), table1), shared_replay_key(find_scheme("baseline-1tb"), table1));
  EXPECT_NE(shared_replay_key(find_scheme("baseline"), table1), shared_replay_key(find_scheme("sfr-v"), table1));
  SharedReplay share;
  (void)run("baseline", Config{}, &share);
  EXPECT_TRUE(same(run("baseline-1tb", Config{}, &share), run("baseline-1tb", Config{})));
  EXPECT_EQ(share.use, SharedReplay::Use::played) << share.why;
}

TEST(MemoryTape, ACompareSharesTheBaselinesReplay) {
  // oovr compare's simulation: baseline-1tb plays the baseline's replay
  // back and says what it says alone.
  SimulationRequest r = courtyard_simulation();
  r.jobs = 2;
  const Simulation both =
      run_simulation(r, {find_scheme("baseline"), find_scheme("baseline-1tb"), find_scheme("sfr-v")}, Config{});
  const Simulation alone = run_simulation(r, {find_scheme("baseline-1tb")}, Config{});
  ASSERT_EQ(both.replays.size(), 3u);
  EXPECT_EQ(both.replays[0], SharedReplay::Use::recorded);
  EXPECT_EQ(both.replays[1], SharedReplay::Use::played);
  EXPECT_EQ(both.replays[2], SharedReplay::Use::none);
  EXPECT_EQ(alone.replays[0], SharedReplay::Use::none);
  EXPECT_TRUE(same(everything(both.results[1]), everything(alone.results[0])));
}

TEST(MemoryTape, RunsTakenAStepAtATimeAndInterleavedAreTheRunsAlone) {
  // oovr compare interleaves its runs' steps (run/simulation.cpp): each
  // run's steps in turn with the others' must give what the run gives
  // alone, a played one included. AFR has four frames in flight: one group
  // a pass, two steps; the others a frame a step, eight.
  const test::RenderedFrames& r = courtyard();
  const FramesInMemory frames(r.traces);
  const MachineSpec table1 = MachineSpec::from_config(Config{});
  SharedReplay recorded;
  WindowRun baseline(find_scheme("baseline"), r.scene, frames, table1, 4, &recorded);
  WindowRun afr(find_scheme("afr"), r.scene, frames, table1, 4);
  WindowRun oo_vr(find_scheme("oo-vr"), r.scene, frames, table1, 4);
  EXPECT_EQ(baseline.steps_left(), 8u);
  EXPECT_EQ(afr.steps_left(), 2u);
  for (WindowRun* w : {&baseline, &afr, &oo_vr})
    while (!w->done()) {
      for (WindowRun* v : {&oo_vr, &afr, &baseline})
        if (!v->done()) v->step();
    }
  std::vector<SchemeResult> runs;
  EXPECT_TRUE(same(everything(baseline.result(&runs), runs), run("baseline", Config{})));
  EXPECT_TRUE(same(everything(afr.result(&runs), runs), run("afr", Config{})));
  EXPECT_TRUE(same(everything(oo_vr.result(&runs), runs), run("oo-vr", Config{})));
  EXPECT_EQ(recorded.use, SharedReplay::Use::recorded);
  ASSERT_TRUE(recorded.tape);
  SharedReplay played = recorded;
  WindowRun faster(find_scheme("baseline-1tb"), r.scene, frames, table1, 4, &played);
  WindowRun again(find_scheme("oo-vr"), r.scene, frames, table1, 4);
  while (!faster.done() || !again.done())
    for (WindowRun* v : {&faster, &again})
      if (!v->done()) v->step();
  EXPECT_EQ(played.use, SharedReplay::Use::played) << played.why;
  EXPECT_TRUE(same(everything(faster.result(&runs), runs), run("baseline-1tb", Config{})));
  EXPECT_TRUE(same(everything(again.result(&runs), runs), run("oo-vr", Config{})));
  EXPECT_THROW(again.step(), Error);               // done: no step left
  EXPECT_THROW((void)again.result(&runs), Error);  // taken already
}

// The frames given, but frame `broken` fails to load, as a window whose
// loader failed does (run/frames.h).
class FramesFailingAt final : public FrameSequence {
 public:
  FramesFailingAt(std::vector<const FrameTrace*> frames, size_t broken) : m_frames(std::move(frames)), m_broken(broken) {}
  size_t size() const override { return m_frames.size(); }
  std::shared_ptr<const FrameTrace> at(size_t k) const override {
    if (k == m_broken) throw Error("frame " + std::to_string(k) + " did not load");
    return FramesInMemory(m_frames).at(k);
  }

 private:
  std::vector<const FrameTrace*> m_frames;
  size_t m_broken;
};

TEST(MemoryTape, ARunWhoseStepFailedTakesNoMoreSteps) {
  // Its memory system is half way through the failed step: a run going on
  // from there would say what no run says.
  const test::RenderedFrames& r = courtyard();
  const FramesFailingAt frames(r.traces, 2);
  WindowRun run(find_scheme("baseline"), r.scene, frames, MachineSpec::from_config(Config{}), 4);
  run.step();
  run.step();
  EXPECT_THROW(run.step(), Error);
  try {
    run.step();
    ADD_FAILURE() << "a failed run took another step";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("failed"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(run.done());
}

TEST(MemoryTape, APlayedRunWhoseCallsDifferPartWayStartsAgainInFull) {
  // The third frame's records differ from the recording's: the played run
  // goes through the warm-up's first two frames, meets the difference on
  // the third, and starts again in full, with all eight steps left.
  const test::RenderedFrames& r = courtyard();
  const std::vector<FrameTrace> changed = with_one_record_changed(2);
  std::vector<const FrameTrace*> pointers;
  for (const FrameTrace& t : changed) pointers.push_back(&t);
  const FramesInMemory frames(pointers);
  const MachineSpec table1 = MachineSpec::from_config(Config{});
  SharedReplay share;
  (void)run("sfr-v", Config{}, &share);
  WindowRun played(find_scheme("sfr-v"), r.scene, frames, table1, 4, &share);
  std::vector<size_t> left;
  while (!played.done() && left.size() < 20) {  // 11 steps; a run that never ends fails here
    played.step();
    left.push_back(played.steps_left());
  }
  EXPECT_EQ(share.use, SharedReplay::Use::mismatched) << share.why;
  EXPECT_EQ(left, (std::vector<size_t>{7, 6, 8, 7, 6, 5, 4, 3, 2, 1, 0}));
  std::vector<SchemeResult> runs, full_runs;
  const SchemeResult full = run_scheme_window(find_scheme("sfr-v"), r.scene, frames, table1, 4, &full_runs);
  EXPECT_TRUE(same(everything(played.result(&runs), runs), everything(full, full_runs)));
}

TEST(MemoryTape, ASimulationIsTheSameOnOneThreadOrMany) {
  // The schemes' runs as oovr compare schedules them, their steps
  // interleaved on three threads, against one thread taking them in turn.
  SimulationRequest r = courtyard_simulation();
  const std::vector<SchemeRef> schemes = {find_scheme("baseline"), find_scheme("afr"), find_scheme("oo-vr"),
                                          find_scheme("baseline-1tb"), find_scheme("object")};
  r.jobs = 1;
  const Simulation one = run_simulation(r, schemes, Config{});
  r.jobs = 3;
  const Simulation three = run_simulation(r, schemes, Config{});
  ASSERT_EQ(one.results.size(), schemes.size());
  ASSERT_EQ(three.results.size(), schemes.size());
  for (size_t i = 0; i < schemes.size(); ++i) {
    EXPECT_TRUE(same(everything(one.results[i]), everything(three.results[i]))) << schemes[i].name;
    EXPECT_EQ(one.replays[i], three.replays[i]) << schemes[i].name;
    // And each as it runs alone, with nothing interleaved.
    const Simulation alone = run_simulation(r, {schemes[i]}, Config{});
    EXPECT_TRUE(same(everything(alone.results.at(0)), everything(three.results[i]))) << schemes[i].name;
  }
  EXPECT_EQ(three.replays[3], SharedReplay::Use::played);
}

TEST(MemoryTape, AnotherMemorySystemIsNotPlayedBack) {
  // A cache of another size answers otherwise: another key, a full run.
  for (const std::string setting : {"cache.l1.size=32KB", "gpms=2", "link.energy_per_bit=250pJ", "shader.triangle_bytes=64"}) {
    const Config c = config_of({setting});
    EXPECT_NE(shared_replay_key(find_scheme("baseline"), MachineSpec::from_config(c)),
              shared_replay_key(find_scheme("baseline"), MachineSpec::from_config(Config{})))
        << setting;
    SharedReplay share;
    (void)run("baseline", Config{}, &share);
    EXPECT_TRUE(same(run("baseline", c, &share), run("baseline", c))) << setting;
    EXPECT_EQ(share.use, SharedReplay::Use::mismatched) << setting;
  }
}

TEST(MemoryTape, ARunWhoseCallsDifferIsRunInFull) {
  // The composition's payload is left out of the key (a scheme that does
  // not compose shares across it); object-level SFR composes, so with
  // depth in the payload its transfers differ from the recording's, the
  // player says so, and the run is made in full.
  const Config depth = config_of({"composition.payload=colour+depth"});
  SharedReplay share;
  (void)run("object", Config{}, &share);
  EXPECT_EQ(shared_replay_key(find_scheme("object"), MachineSpec::from_config(depth)),
            shared_replay_key(find_scheme("object"), MachineSpec::from_config(Config{})));
  EXPECT_TRUE(same(run("object", depth, &share), run("object", depth)));
  EXPECT_EQ(share.use, SharedReplay::Use::mismatched);
  EXPECT_NE(share.why.find("differs from the recording"), std::string::npos) << share.why;
  // The baseline composes nothing: it plays across the payload.
  SharedReplay baseline;
  (void)run("baseline", Config{}, &baseline);
  EXPECT_TRUE(same(run("baseline", depth, &baseline), run("baseline", depth)));
  EXPECT_EQ(baseline.use, SharedReplay::Use::played) << baseline.why;
}

TEST(MemoryTape, ATapeIsPlayedOnlyOnItsOwnFrames) {
  // The same frames but for one record, which writes other depth lines:
  // the scheme's calls are the recording's (the same records, in the same
  // order), but the frames are folded into the calls' hash, so the run is
  // made in full rather than given the recording's traffic.
  const test::RenderedFrames& r = courtyard();
  const std::vector<FrameTrace> changed = with_one_record_changed(0);
  std::vector<const FrameTrace*> frames;
  for (const FrameTrace& t : changed) frames.push_back(&t);
  const auto on_changed = [&](SharedReplay* share) {
    std::vector<SchemeResult> runs;
    const SchemeResult s = run_scheme_window(find_scheme("sfr-v"), r.scene, FramesInMemory(frames),
                                             MachineSpec::from_config(Config{}), 4, &runs, share);
    return everything(s, runs);
  };
  SharedReplay share;
  const std::string recorded = run("sfr-v", Config{}, &share);
  const std::string full = on_changed(nullptr);
  ASSERT_FALSE(same(full, recorded)) << "the changed record changed nothing, so this test could not tell";
  EXPECT_TRUE(same(on_changed(&share), full));
  EXPECT_EQ(share.use, SharedReplay::Use::mismatched) << share.why;
}

TEST(MemoryTape, APlayerChecksEveryAnswersCallsAndKind) {
  MemoryTape tape("k");
  UnitTraffic t;
  t.reset(2, 2);
  t.accesses = 7;
  t.link_bytes[1] = uint64_t(1) << 50;  // wider than a packed word
  t.inter_gpm_bytes[2] = 128;
  tape.traffic(11, t);
  tape.value(12, 42);
  MemoryTape::FrameEnd e;
  e.local_dram_bytes = 5;
  tape.frame_end(13, e);
  const auto shared = std::make_shared<const MemoryTape>(std::move(tape));
  {
    MemoryTape::Player p(shared);
    UnitTraffic back;
    back.reset(2, 2);
    back.l1_hits = 3;  // overwritten: every field comes from the tape
    p.traffic(11, back);
    EXPECT_EQ(back.accesses, 7u);
    EXPECT_EQ(back.l1_hits, 0u);
    EXPECT_EQ(back.link_bytes[1], uint64_t(1) << 50);
    EXPECT_EQ(back.inter_gpm_bytes[2], 128u);
    EXPECT_FALSE(p.at_end());
    EXPECT_EQ(p.value(12), 42u);
    EXPECT_EQ(p.frame_end(13).local_dram_bytes, 5u);
    EXPECT_TRUE(p.at_end());
    EXPECT_THROW(p.value(14), TapeMismatch);  // past the end
  }
  MemoryTape::Player wrong_hash(shared);
  UnitTraffic back;
  back.reset(2, 2);
  EXPECT_THROW(wrong_hash.traffic(10, back), TapeMismatch);
  MemoryTape::Player wrong_kind(shared);
  EXPECT_THROW((void)wrong_kind.value(11), TapeMismatch);
  MemoryTape::Player narrower(shared);
  back.reset(2, 1);  // a machine with fewer links than the recording's
  EXPECT_THROW(narrower.traffic(11, back), TapeMismatch);
}

}  // namespace
}  // namespace oovr
