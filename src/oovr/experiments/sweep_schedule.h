// The order in which the sweep engine (sweep_run.h) hands out its work, apart
// from the work itself: one pool over all groups of points (a group: the
// points over the same traces), each group loaded before its points run.
// The engine asks it what a free worker does next; predict_schedule asks it
// the same questions with measured durations in place of the work, to tell
// what a sweep would take on more workers than the machine measured has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace oovr {

class SweepSchedule {
 public:
  // `sizes`: each group's points, groups in the order they run. With one
  // worker, a group loads when the one before is done. With more, groups
  // load while the groups before them run, up to workers / 4 groups (at
  // least one) ahead of the earliest held, several at once, while the traces
  // held (a loading group counted as the largest loaded so far) stay within
  // half of `memory_budget` bytes.
  SweepSchedule(std::vector<size_t> sizes, unsigned workers, uint64_t memory_budget);

  struct Action {
    enum class Kind { load, point, wait, stop };
    Kind kind = Kind::stop;
    size_t group = 0;
    size_t point = 0;  // the point's place in its group
  };
  // What a free worker does: load the next group, run a point of the
  // earliest loaded group that has one left, wait for a load or a point to
  // end, or stop (nothing is left to hand out).
  Action next();
  // A load has ended: `ok` with `bytes` of traces held, or failed (its
  // points will not run; the group is let go at once).
  void loaded(size_t group, bool ok, uint64_t bytes);
  // A point of `group` has ended; true when it was the group's last, and
  // the group is let go (its traces can be freed).
  bool point_done(size_t group);

  size_t groups() const { return m_groups.size(); }
  // Whether a group's load has begun and it is not yet let go.
  bool held(size_t group) const;
  // Groups whose load has begun.
  size_t started() const { return m_next_load; }

 private:
  struct Group {
    size_t size = 0, handed = 0, done = 0;
    bool loaded = false, ok = false, released = false;
    uint64_t bytes = 0;
  };
  bool may_load() const;
  void release(Group& g);

  std::vector<Group> m_groups;
  size_t m_ahead;  // groups that may be held besides the earliest
  uint64_t m_budget;
  uint64_t m_largest = 0;  // bytes of the largest group loaded so far
  bool m_any_loaded = false;
  size_t m_next_load = 0;
  size_t m_held = 0;
};

// One group's measured work: its load, then each of its points (seconds).
struct GroupDurations {
  double load_s = 0;
  std::vector<double> points_s;
};

struct PredictedSchedule {
  double wall_s = 0;  // from the first load's start to the last point's end
  double busy_s = 0;  // the tasks' durations summed
  double efficiency(unsigned workers) const { return wall_s > 0 ? busy_s / (wall_s * workers) : 1; }
};

// The sweep's time on `workers` workers with these durations (measured on
// one worker, where no task contends with another for the machine), as the
// engine schedules it; with `barrier`, as an engine that loads each group on
// one worker and then runs its points with a barrier at the group's end
// (oovr before one pool). Traces held are not counted against the budget.
PredictedSchedule predict_schedule(const std::vector<GroupDurations>& groups, unsigned workers, bool barrier);

// Seconds a sweep of `total` points has left, `finished` (ascending) being
// when each finished point ended and `now` the time, both in seconds from
// the start: the points left at the recent rate (over the last quarter of
// the finished points, at least 8 of them) or at the whole run's, whichever
// is slower. A sweep's late points are often its costly ones (the paper's
// game levels after the built-in scenes, its larger resolutions), so the
// whole run's mean alone runs low; the recent rate follows them. NaN while
// nothing has finished; 0 once everything has.
double estimate_seconds_left(std::span<const double> finished, size_t total, double now);

}  // namespace oovr
