// The timeline (oovr simulate --timeline; run/timeline.h): every unit as
// the timing engine ran it, and as Trace Event Format JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "oovr/core/error.h"
#include "oovr/run/timeline.h"
#include "oovr/schemes/i_scheme.h"
#include "test_util.h"

namespace oovr {
namespace {

const test::RenderedFrames& courtyard() {
  static const std::unique_ptr<test::RenderedFrames> r = test::render_builtin("courtyard", 320, 240, 30, 4);
  return *r;
}

SchemeResult run(const std::string& scheme, bool timeline) {
  const auto& r = courtyard();
  MachineSpec machine = MachineSpec::from_config(Config());
  machine.timeline = timeline;
  return run_scheme_window(find_scheme(scheme), r.scene, FramesInMemory(r.traces), machine, 4);
}

// The union of [start, finish) of a set of intervals.
double covered(std::vector<std::pair<double, double>> v) {
  std::sort(v.begin(), v.end());
  double end = -1, sum = 0;
  for (const auto& [a, b] : v) {
    if (a >= end) sum += b - a;
    else if (b > end) sum += b - end;
    end = std::max(end, b);
  }
  return sum;
}

TEST(Timeline, ItsSpansAddUpToEachGpmsBusyTime) {
  for (const char* scheme : {"baseline", "oo-vr", "chopin"}) {
    const SchemeResult r = run(scheme, true);
    ASSERT_FALSE(r.timeline.empty()) << scheme;
    // A GPM is busy while its front end, pipeline or ROPs work: per frame,
    // the union of those units' spans; the result is the frames' mean.
    std::map<std::pair<int, int>, std::vector<std::pair<double, double>>> spans;  // (gpm, frame)
    int frames = 0;
    for (const TimelineUnit& u : r.timeline) {
      frames = std::max(frames, u.frame + 1);
      EXPECT_LE(u.start, u.work_done);
      EXPECT_LE(u.work_done, u.finish);
      if (u.kind == TimelineUnit::Kind::transfer || u.kind == TimelineUnit::Kind::prealloc) continue;
      spans[{u.gpm, u.frame}].push_back({u.start, u.finish});
    }
    EXPECT_EQ(frames, 4);
    for (int g = 0; g < r.gpms; ++g) {
      double busy = 0;
      for (int f = 0; f < frames; ++f) busy += covered(spans[{g, f}]);
      EXPECT_NEAR(busy / frames, r.gpm_busy_s[size_t(g)], 1e-12 * r.frame_latency_s) << scheme << " GPM " << g;
    }
    // Each frame's last unit ends at its latency; frames follow each other.
    std::vector<double> last(size_t(frames), 0), offset(size_t(frames), 0);
    for (const TimelineUnit& u : r.timeline) {
      last[size_t(u.frame)] = std::max(last[size_t(u.frame)], u.finish);
      offset[size_t(u.frame)] = u.offset;
    }
    for (int f = 0; f < frames; ++f) {
      EXPECT_NEAR(last[size_t(f)], r.frame_latencies_s[size_t(f)], 1e-15) << scheme;
      if (f) {
        EXPECT_NEAR(offset[size_t(f)], offset[size_t(f - 1)] + r.frame_latencies_s[size_t(f - 1)], 1e-15);
      }
    }
    // Keeping it changes no number.
    const SchemeResult plain = run(scheme, false);
    EXPECT_TRUE(plain.timeline.empty());
    EXPECT_EQ(plain.frame_latencies_s, r.frame_latencies_s) << scheme;
    EXPECT_EQ(plain.gpm_busy_s, r.gpm_busy_s) << scheme;
  }
}

TEST(Timeline, OOVRMarksEachBatchAndEachDecision) {
  const SchemeResult r = run("oo-vr", true);
  const Stat* batches = r.stats.find("oo-vr", "batches");
  ASSERT_NE(batches, nullptr);
  const size_t per_frame = size_t(batches->value), frames = r.frame_latencies_s.size();
  std::map<std::pair<int, int>, int> decisions, spans;  // (frame, batch) -> count
  for (const TimelineMark& m : r.marks) {
    int batch = -1, gpm = -1;
    for (const auto& [k, v] : m.args) {
      if (k == "batch") batch = int(v);
      if (k == "gpm") gpm = int(v);
    }
    ASSERT_GE(batch, 0) << m.name;
    if (m.category == "decision") {
      ++decisions[{m.frame, batch}];
      EXPECT_EQ(gpm, m.gpm);
      EXPECT_LT(m.finish, 0) << "an instant";
    } else {
      ASSERT_EQ(m.category, "batch");
      ++spans[{m.frame, batch}];
      EXPECT_LE(m.start, m.finish);
      EXPECT_LE(m.finish, r.frame_latencies_s[size_t(m.frame)] + 1e-15);
    }
  }
  // Every batch of every frame: sent once, and ran as one span on its GPM.
  EXPECT_EQ(decisions.size(), per_frame * frames);
  EXPECT_EQ(spans.size(), per_frame * frames);
  for (const auto& [key, n] : decisions) EXPECT_EQ(n, 1);
  for (const auto& [key, n] : spans) EXPECT_EQ(n, 1);
  // Without a timeline, nothing is kept.
  EXPECT_TRUE(run("oo-vr", false).marks.empty());
}

TEST(Timeline, ChopinMarksEachCompositionGroupOnTheGpmsThatWorkedInIt) {
  const SchemeResult r = run("chopin", true);
  const Stat* groups = r.stats.find("chopin", "groups");
  ASSERT_NE(groups, nullptr);
  std::map<std::pair<int, int>, int> spans;  // (frame, group) -> GPMs
  for (const TimelineMark& m : r.marks) {
    ASSERT_EQ(m.category, "group");
    int group = -1;
    for (const auto& [k, v] : m.args)
      if (k == "group") group = int(v);
    ASSERT_GE(group, 0);
    ++spans[{m.frame, group}];
    EXPECT_LE(m.start, m.finish);
    EXPECT_LE(m.gpm, r.gpms - 1);
  }
  // Every group of every frame, on at least one GPM and at most all.
  EXPECT_EQ(spans.size(), size_t(groups->value) * r.frame_latencies_s.size());
  for (const auto& [key, n] : spans) {
    EXPECT_GE(n, 1);
    EXPECT_LE(n, r.gpms);
  }
}

TEST(Timeline, GpupdMarksEachBatchsProjectionAndRenderingPerGpm) {
  const SchemeResult r = run("gpupd", true);
  std::map<std::pair<int, int>, int> projection, rendering;  // (frame, batch) -> GPMs
  for (const TimelineMark& m : r.marks) {
    int batch = -1;
    for (const auto& [k, v] : m.args)
      if (k == "batch") batch = int(v);
    ASSERT_GE(batch, 0);
    EXPECT_LE(m.start, m.finish);
    if (m.category == "projection") ++projection[{m.frame, batch}];
    else if (m.category == "rendering") ++rendering[{m.frame, batch}];
    else ADD_FAILURE() << m.category;
  }
  // Every GPM projects its share of every batch; the batches it renders
  // are those with primitives in its strip; all of them in every frame.
  ASSERT_FALSE(projection.empty());
  for (const auto& [key, n] : projection) EXPECT_EQ(n, r.gpms);
  EXPECT_EQ(rendering.size(), projection.size());
  std::set<int> frames;
  for (const auto& [key, n] : projection) frames.insert(key.first);
  EXPECT_EQ(frames.size(), r.frame_latencies_s.size());
}

// What Perfetto's and chrome://tracing's importers need of complete ("X")
// events: on one thread, each span either follows the one before or lies
// wholly inside it (a stack); a span that overlaps another's end is
// dropped or misdrawn. Every scheme that marks spans, with waits inside
// units: spans nest or follow on every track, to rounding.
TEST(Timeline, SpansNestOrFollowOnEveryTrackAsViewersRequire) {
  for (const char* scheme : {"oo-vr", "chopin", "gpupd", "baseline", "afr"}) {
    const SchemeResult r = run(scheme, true);
    const nlohmann::json j = nlohmann::json::parse(timeline_json(r, 1'000'000).json);
    std::map<std::pair<int, int>, std::vector<std::pair<double, double>>> tracks;
    size_t spans = 0;
    for (const auto& e : j["traceEvents"]) {
      ASSERT_TRUE(e.contains("ph") && e.contains("pid") && e.contains("name")) << e.dump();
      if (e["ph"] != "X") continue;
      ASSERT_TRUE(e.contains("ts") && e.contains("dur") && e.contains("tid")) << e.dump();
      tracks[{e["pid"], e["tid"]}].emplace_back(double(e["ts"]), double(e["ts"]) + double(e["dur"]));
      ++spans;
    }
    EXPECT_GT(spans, 0u) << scheme;
    const double eps = 1e-6;  // µs: the rounding of two sums of the same times
    for (auto& [track, v] : tracks) {
      // Longer first at one start, as a viewer stacks them.
      std::sort(v.begin(), v.end(),
                [](const auto& a, const auto& b) { return a.first < b.first || (a.first == b.first && a.second > b.second); });
      std::vector<double> open;  // ends of the spans enclosing the current one
      for (const auto& [a, b] : v) {
        while (!open.empty() && open.back() <= a + eps) open.pop_back();
        if (!open.empty()) {
          EXPECT_LE(b, open.back() + eps) << scheme << ": a span on pid " << track.first << " tid " << track.second << " from "
                                          << a << " to " << b << " overlaps the end (" << open.back() << ") of one it starts in";
        }
        open.push_back(b);
      }
    }
  }
}

TEST(Timeline, TraceEventFormatNamesEveryTrackAndBoundsItsSize) {
  const SchemeResult r = run("oo-vr", true);
  const TimelineText t = timeline_json(r, 1'000'000);
  EXPECT_EQ(t.units, r.timeline.size());
  EXPECT_EQ(t.omitted, 0u);
  const nlohmann::json j = nlohmann::json::parse(t.json);
  ASSERT_TRUE(j.at("traceEvents").is_array());
  std::map<std::string, int> kinds;
  std::map<std::pair<int, int>, std::string> named;  // (pid, tid): its thread_name
  std::map<int, std::string> processes;
  size_t spans = 0, waits = 0;
  for (const auto& e : j["traceEvents"]) {
    const std::string ph = e.at("ph");
    if (ph == "M" && e["name"] == "process_name") processes[e["pid"]] = e["args"]["name"];
    if (ph == "M" && e["name"] == "thread_name") named[{e["pid"], e["tid"]}] = e["args"]["name"];
    if (ph == "i") ++kinds[e["cat"]];
    if (ph != "X" || !e.contains("cat")) continue;
    ++kinds[e["cat"]];
    if (e["cat"] == "batch") continue;  // the scheme's marks, counted apart
    if (e["cat"] == "wait") {           // inside a unit, counted apart
      ++waits;
      continue;
    }
    ++spans;
    EXPECT_GE(double(e["dur"]), 0.0);
    EXPECT_TRUE(named.count({e["pid"], e["tid"]})) << "a span on an unnamed thread: " << e.dump();
    if (e["cat"] == "transfer") {
      // "transfer A -> B" on the links' track "GPM A -> GPM B" (or a lane of it).
      const std::string name = e["name"], track = named[{e["pid"], e["tid"]}];
      int a = -1, b = -1, c = -1, d = -1;
      EXPECT_EQ(std::sscanf(name.c_str(), "transfer %d -> %d", &a, &b), 2) << name;
      EXPECT_EQ(std::sscanf(track.c_str(), "GPM %d -> GPM %d", &c, &d), 2) << track;
      EXPECT_TRUE(a >= 0 && a < r.gpms && b >= 0 && b < r.gpms && a != b) << name;
      EXPECT_EQ(std::pair(a, b), std::pair(c, d)) << name << " on " << track;
    }
  }
  EXPECT_EQ(spans, r.timeline.size());
  // A wait inside every unit that had latency after its work, ending with it.
  size_t waited = 0;
  for (const TimelineUnit& u : r.timeline) waited += u.finish > u.work_done;
  EXPECT_GT(waited, 0u);
  EXPECT_EQ(waits, waited);
  EXPECT_EQ(t.waits, waited);
  std::map<std::pair<int, int>, std::vector<std::pair<double, double>>> units_on;  // (pid, tid): (start, end) in µs
  for (const auto& e : j["traceEvents"])
    if (e["ph"] == "X" && e.contains("cat") && e["cat"] != "wait" && e["cat"] != "batch")
      units_on[{e["pid"], e["tid"]}].emplace_back(double(e["ts"]), double(e["ts"]) + double(e["dur"]));
  for (const auto& e : j["traceEvents"]) {
    if (e["ph"] != "X" || !e.contains("cat") || e["cat"] != "wait") continue;
    const double from = e["ts"], to = from + double(e["dur"]);
    bool inside = false;
    for (const auto& [a, b] : units_on[{e["pid"], e["tid"]}]) inside |= a <= from + 1e-6 && std::abs(b - to) < 1e-6;
    EXPECT_TRUE(inside) << "a wait that does not end its unit: " << e.dump();
  }
  for (const char* k : {"draw", "geometry", "tiles", "compose", "transfer"}) EXPECT_GT(kinds[k], 0) << k;
  EXPECT_EQ(size_t(kinds["batch"]) + size_t(kinds["decision"]), r.marks.size());
  EXPECT_EQ(processes[0], "GPM 0");
  EXPECT_EQ(processes[r.gpms], "links");
  EXPECT_EQ(processes[r.gpms + 1], "frames");
  EXPECT_EQ(j["otherData"]["units"], r.timeline.size());
  // Bounded: the earliest units only, and the file says how many are left out.
  const TimelineText small = timeline_json(r, 10);
  EXPECT_EQ(small.units, 10u);
  EXPECT_EQ(small.omitted, r.timeline.size() - 10);
  const nlohmann::json s = nlohmann::json::parse(small.json);
  EXPECT_EQ(s["otherData"]["units_left_out"], r.timeline.size() - 10);
  double latest = 0;
  for (const auto& e : s["traceEvents"])
    if (e["ph"] == "X" && e.contains("cat") && e["cat"] != "batch") latest = std::max(latest, double(e["ts"]));
  size_t earlier = 0;
  for (const TimelineUnit& u : r.timeline) earlier += (u.offset + u.start) * 1e6 <= latest;
  EXPECT_GE(earlier, 10u);
  EXPECT_LT(earlier, r.timeline.size() / 2) << "not the earliest";
  // A run that kept none is refused.
  EXPECT_THROW((void)timeline_json(run("oo-vr", false), 10), Error);
}

}  // namespace
}  // namespace oovr
