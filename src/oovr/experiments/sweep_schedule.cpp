#include "oovr/experiments/sweep_schedule.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "oovr/core/error.h"

namespace oovr {

SweepSchedule::SweepSchedule(std::vector<size_t> sizes, unsigned workers, uint64_t memory_budget)
    : m_ahead(workers <= 1 ? 0 : std::max<size_t>(1, workers / 4)), m_budget(memory_budget) {
  m_groups.resize(sizes.size());
  for (size_t g = 0; g < sizes.size(); ++g) m_groups[g].size = sizes[g];
}

bool SweepSchedule::held(size_t group) const { return group < m_next_load && !m_groups.at(group).released; }

// The next group may load when no group is held. With workers to spare, also
// ahead of the groups held: loads then overlap the points before them, and
// on many workers several loads overlap one another (a group's load is a
// sizeable share of its points' time: the paper's evaluation, on one
// worker, loads for 7% of its time), within the traces' half budget.
bool SweepSchedule::may_load() const {
  if (m_next_load == m_groups.size()) return false;
  if (m_held == 0) return true;
  if (m_held > m_ahead || !m_any_loaded) return false;  // no size to go by before a first load ends
  uint64_t bytes = m_largest;                           // the group that would load
  for (size_t g = 0; g < m_next_load; ++g)
    if (!m_groups[g].released) bytes += m_groups[g].loaded ? m_groups[g].bytes : m_largest;
  return bytes <= m_budget / 2;
}

SweepSchedule::Action SweepSchedule::next() {
  // A load first: it then overlaps the points of the group before it.
  if (may_load()) {
    ++m_held;
    return {Action::Kind::load, m_next_load++, 0};
  }
  for (size_t k = 0; k < m_next_load; ++k) {
    Group& g = m_groups[k];
    if (g.loaded && g.ok && g.handed < g.size) return {Action::Kind::point, k, g.handed++};
  }
  if (m_next_load < m_groups.size()) return {Action::Kind::wait, 0, 0};
  for (const Group& g : m_groups)
    if (!g.released) return {Action::Kind::wait, 0, 0};  // a load or points still running
  return {Action::Kind::stop, 0, 0};
}

void SweepSchedule::release(Group& g) {
  g.released = true;
  g.bytes = 0;
  --m_held;
}

void SweepSchedule::loaded(size_t group, bool ok, uint64_t bytes) {
  Group& g = m_groups.at(group);
  if (group >= m_next_load || g.loaded) throw Error("SweepSchedule: group " + std::to_string(group) + " was not loading");
  g.loaded = true;
  g.ok = ok;
  g.bytes = bytes;
  m_largest = std::max(m_largest, bytes);
  m_any_loaded = true;
  if (!ok || g.size == 0) {
    g.handed = g.done = g.size;
    release(g);
  }
}

bool SweepSchedule::point_done(size_t group) {
  Group& g = m_groups.at(group);
  if (g.done >= g.handed) throw Error("SweepSchedule: no point of group " + std::to_string(group) + " was running");
  if (++g.done < g.size) return false;
  release(g);
  return true;
}

namespace {

PredictedSchedule barrier_schedule(const std::vector<GroupDurations>& groups, unsigned workers) {
  PredictedSchedule p;
  double t = 0;
  for (const GroupDurations& g : groups) {
    t += g.load_s;
    p.busy_s += g.load_s;
    std::priority_queue<double, std::vector<double>, std::greater<>> free;
    for (unsigned w = 0; w < workers; ++w) free.push(t);
    double end = t;
    for (double d : g.points_s) {
      const double start = free.top();
      free.pop();
      free.push(start + d);
      end = std::max(end, start + d);
      p.busy_s += d;
    }
    t = end;
  }
  p.wall_s = t;
  return p;
}

}  // namespace

PredictedSchedule predict_schedule(const std::vector<GroupDurations>& groups, unsigned workers, bool barrier) {
  if (workers == 0) throw Error("predict_schedule: no workers");
  if (barrier) return barrier_schedule(groups, workers);
  std::vector<size_t> sizes;
  for (const auto& g : groups) sizes.push_back(g.points_s.size());
  SweepSchedule s(sizes, workers, std::numeric_limits<uint64_t>::max());
  // Events: a task's end, in time order (ties: in the order they began, as
  // one worker's end is seen before the next decision).
  struct Event {
    double at;
    size_t serial;
    bool load;
    size_t group;
    bool operator>(const Event& o) const { return at != o.at ? at > o.at : serial > o.serial; }
  };
  std::priority_queue<Event, std::vector<Event>, std::greater<>> events;
  PredictedSchedule p;
  size_t serial = 0;
  double now = 0;
  unsigned idle = workers;  // workers waiting for an event
  for (;;) {
    // Every idle worker asks what to do, now.
    while (idle > 0) {
      const SweepSchedule::Action a = s.next();
      if (a.kind == SweepSchedule::Action::Kind::wait || a.kind == SweepSchedule::Action::Kind::stop) break;
      const double d = a.kind == SweepSchedule::Action::Kind::load ? groups[a.group].load_s : groups[a.group].points_s[a.point];
      p.busy_s += d;
      events.push({now + d, serial++, a.kind == SweepSchedule::Action::Kind::load, a.group});
      --idle;
    }
    if (events.empty()) break;
    const Event e = events.top();
    events.pop();
    now = e.at;
    if (e.load) s.loaded(e.group, true, 0);
    else (void)s.point_done(e.group);
    ++idle;
  }
  p.wall_s = now;
  return p;
}

double estimate_seconds_left(std::span<const double> finished, size_t total, double now) {
  const size_t n = finished.size();
  if (n >= total) return 0;
  if (n == 0 || now <= 0) return std::nan("");
  const double left = double(total - n);
  const double whole = now / double(n) * left;
  // The recent window: its points over the time since the point before it
  // ended (or since the start).
  const size_t window = std::max<size_t>(8, n / 4);
  if (n <= window) return whole;
  const double since = finished[n - window - 1];
  const double span = now - since;
  if (span <= 0) return whole;
  return std::max(whole, span / double(window) * left);
}

}  // namespace oovr
