#include "oovr/run/timeline.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>

#include "oovr/core/error.h"

namespace oovr {

namespace {

// Lanes a track may spread over (its thread ids: track * kLanes + lane);
// past the last, units share it.
constexpr int kLanes = 1000;
const char* const kThreads[] = {
    "front end (draws)",     "pipeline", "composition", "copies in (pre-allocation)", "the scheme's spans (batches)",
    "the scheme's decisions"};
constexpr int kGpmTracks = 6;

// The thread of a GPM's process a unit runs on.
int gpm_thread(TimelineUnit::Kind k) {
  switch (k) {
    case TimelineUnit::Kind::command: return 0;
    case TimelineUnit::Kind::compose: return 2;
    case TimelineUnit::Kind::prealloc: return 3;
    default: return 1;
  }
}

nlohmann::ordered_json name_event(const char* what, int pid, int tid, const std::string& name) {
  nlohmann::ordered_json e;
  e["name"] = what;
  e["ph"] = "M";
  e["pid"] = pid;
  e["tid"] = tid;
  e["args"] = {{"name", name}};
  return e;
}

// Spans of one track that overlap (composition, copies, transfers beside
// each other, a scheme's spans) go on lanes of their own: a viewer nests the
// spans of one thread, and these do not nest. Spans come in order of start.
class Lanes {
 public:
  // The thread of a span [start, finish) of track `track` of process `pid`:
  // the first lane free by `start`, or a new one, whose thread is named
  // `name` ("name (k)" past the first lane; the first lane only when
  // `name_first`, the others having their names already).
  int place(int pid, int track, double start, double finish, const std::string& name, bool name_first,
            nlohmann::ordered_json& events) {
    std::vector<double>& ends = m_ends[{pid, track}];
    size_t lane = 0;
    while (lane < ends.size() && ends[lane] > start) ++lane;
    if (lane == ends.size()) {
      ends.push_back(0);
      if (name_first || lane > 0)
        events.push_back(name_event("thread_name", pid, track * kLanes + int(lane),
                                    lane ? name + " (" + std::to_string(lane + 1) + ")" : name));
    }
    ends[lane] = finish;
    return track * kLanes + int(std::min<size_t>(lane, kLanes - 1));
  }

 private:
  std::map<std::pair<int, int>, std::vector<double>> m_ends;  // (pid, track) -> each lane's last finish
};

}  // namespace

TimelineText timeline_json(const SchemeResult& r, size_t max_events) {
  if (r.timeline.empty()) throw Error(r.scheme + ": the run kept no timeline (run it with MachineSpec::timeline)");
  const int n = r.gpms;
  const int links_pid = n, frames_pid = n + 1;
  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  for (int g = 0; g < n; ++g) {
    events.push_back(name_event("process_name", g, 0, "GPM " + std::to_string(g)));
    events.push_back(name_event("process_sort_index", g, 0, std::to_string(g)));
    for (int t = 0; t < kGpmTracks; ++t) events.push_back(name_event("thread_name", g, t * kLanes, kThreads[t]));
  }
  events.push_back(name_event("process_name", links_pid, 0, "links"));
  events.push_back(name_event("process_name", frames_pid, 0, "frames"));
  // The frames, one after the other.
  double end = 0;
  int frame = -1;
  for (const TimelineUnit& u : r.timeline)
    if (u.frame != frame) {
      frame = u.frame;
      const double lat = frame < int(r.frame_latencies_s.size()) ? r.frame_latencies_s[size_t(frame)] : 0;
      nlohmann::ordered_json e;
      e["name"] = "frame " + std::to_string(frame);
      e["ph"] = "X";
      e["ts"] = u.offset * 1e6;
      e["dur"] = lat * 1e6;
      e["pid"] = frames_pid;
      e["tid"] = 0;
      events.push_back(e);
      end = std::max(end, u.offset + lat);
    }
  // The units, earliest first, at most max_events.
  std::vector<size_t> order(r.timeline.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return r.timeline[a].offset + r.timeline[a].start < r.timeline[b].offset + r.timeline[b].start;
  });
  TimelineText out;
  Lanes lanes;
  for (size_t i : order) {
    if (out.units == max_events) {
      ++out.omitted;
      continue;
    }
    const TimelineUnit& u = r.timeline[i];
    nlohmann::ordered_json e;
    std::string name = timeline_kind_name(u.kind);
    if (u.object >= 0) name += " object " + std::to_string(u.object);
    if (u.kind == TimelineUnit::Kind::transfer) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, wrongly) of
      // overlapping copies in the chain of + that said the same.
      name += ' ';
      name += std::to_string(u.from);
      name += " -> ";
      name += std::to_string(u.gpm);
    }
    e["name"] = name;
    e["cat"] = timeline_kind_name(u.kind);
    e["ph"] = "X";
    e["ts"] = (u.offset + u.start) * 1e6;
    e["dur"] = (u.finish - u.start) * 1e6;
    const bool link = u.kind == TimelineUnit::Kind::transfer;
    const int pid = link ? links_pid : std::max(u.gpm, 0);
    const int track = link ? u.from * n + u.gpm : gpm_thread(u.kind);
    e["pid"] = pid;
    e["tid"] = lanes.place(
        pid, track, u.offset + u.start, u.offset + u.finish,
        link ? "GPM " + std::to_string(u.from) + " -> GPM " + std::to_string(u.gpm) : std::string(kThreads[track]), link, events);
    e["args"] = {{"frame", u.frame}, {"work_us", (u.work_done - u.start) * 1e6}, {"latency_us", (u.finish - u.work_done) * 1e6}};
    const nlohmann::ordered_json unit_tid = e["tid"];
    events.push_back(e);
    ++out.units;
    // Its wait on memory and links (the reads outstanding when its work is
    // done, the link hops of what it sends) as a span inside it, so a
    // track shows where a GPM waited rather than worked.
    if (u.finish > u.work_done) {
      nlohmann::ordered_json w;
      w["name"] = link ? "in flight over the links" : "waiting on memory and links";
      w["cat"] = "wait";
      w["ph"] = "X";
      w["ts"] = (u.offset + u.work_done) * 1e6;
      w["dur"] = (u.finish - u.work_done) * 1e6;
      w["pid"] = pid;
      w["tid"] = unit_tid;
      w["args"] = {{"frame", u.frame}};
      events.push_back(w);
      ++out.waits;
    }
  }
  // The scheme's marks: spans on lanes of their own track, instants on theirs.
  for (const TimelineMark& m : r.marks) {
    nlohmann::ordered_json e;
    e["name"] = m.name;
    e["cat"] = m.category;
    e["ts"] = (m.offset + m.start) * 1e6;
    e["pid"] = std::max(m.gpm, 0);
    nlohmann::ordered_json args = nlohmann::ordered_json::object();
    args["frame"] = m.frame;
    for (const auto& [k, v] : m.args) {
      if (v == std::floor(v) && std::abs(v) < 1e15) args[k] = int64_t(v);  // counts and ids as whole numbers
      else args[k] = v;
    }
    e["args"] = args;
    if (m.finish < 0) {
      e["ph"] = "i";
      e["s"] = "t";
      e["tid"] = 5 * kLanes;
    } else {
      e["ph"] = "X";
      e["dur"] = (m.finish - m.start) * 1e6;
      e["tid"] = lanes.place(std::max(m.gpm, 0), 4, m.offset + m.start, m.offset + m.finish, kThreads[4], false, events);
    }
    events.push_back(e);
  }
  nlohmann::ordered_json doc;
  doc["traceEvents"] = events;
  doc["displayTimeUnit"] = "ns";
  doc["otherData"] = {{"scheme", r.scheme},
                      {"gpms", n},
                      {"frames", r.frame_latencies_s.size()},
                      {"units", r.timeline.size()},
                      {"units_written", out.units},
                      {"units_left_out", out.omitted},
                      {"waits", out.waits},
                      {"marks", r.marks.size()},
                      {"end_us", end * 1e6}};
  out.json = doc.dump() + "\n";
  return out;
}

}  // namespace oovr
