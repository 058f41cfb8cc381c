// The event-driven timing engine (DESIGN.md, "How work becomes time").
//
// Work units demand amounts of resources (shader instructions, texture
// samples, ROP pixels, DRAM bytes, link bytes, ...); each resource has a
// capacity per second. Units in one queue (a GPM's pipeline) run one after
// another; units of different queues run at the same time and share every
// resource they both use. A fluid model decides how fast each runs:
//
//   a unit progresses at one rate, a fraction of its work per second, the
//   same for all it demands; resources are shared max-min fairly and
//   work-conservingly among the running units that demand them
//   (timing/sharing.h).
//
// Between two events (a unit starting or finishing) every rate is constant,
// so the engine jumps from event to event. A unit's latency (DRAM, link
// hops) is added after its work, without holding resources; its queue's next
// unit starts only after it. Ties are broken by unit id: the result is the
// same on every run and for any thread count.
//
// Units may also be added while the engine runs, from the `on_finish` hook
// (a runtime scheduler deciding what a GPM does next): they join the run at
// the current time, and may ask about every unit's progress.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "oovr/core/stats.h"
#include "oovr/timing/sharing.h"

namespace oovr {

class TimingEngine {
 public:
  struct Unit {
    int queue = -1;          // -1: runs as soon as its dependencies allow
    Demand demand;           // (resource, amount) pairs
    double latency = 0;      // seconds added after the work
    std::vector<int> after;  // units that must finish first
  };
  struct UnitTime {
    double start = 0, work_done = 0, finish = 0;  // seconds
  };
  struct Result {
    std::vector<UnitTime> units;
    std::vector<double> queue_busy;     // seconds each queue had a unit running (work and latency)
    std::vector<double> resource_used;  // amount of each resource consumed
    double makespan = 0;                // finish of the last unit
  };

  void set_sharing(Sharing s) { m_sharing = s; }
  // Adds a resource with `capacity` units per second; returns its id.
  // `name` is its location in statistics ("gpm[0].shader", "link[0->1]");
  // `unit` that of its amounts ("B"; "s" for time held; "" for counts).
  int add_resource(std::string name, double capacity, std::string unit = "");
  int add_queue(std::string name);
  // Adds a unit; its dependencies must be units added before. Returns its id.
  int add_unit(Unit u);

  const std::string& resource_name(int r) const { return m_resource_names[size_t(r)]; }
  double capacity(int r) const { return m_capacity[size_t(r)]; }
  size_t resources() const { return m_capacity.size(); }
  size_t queues() const { return m_queue_names.size(); }
  size_t units() const { return m_units.size(); }

  // Runs every unit to its end. `on_finish(id)` is called when a unit ends
  // (work and latency), in time order, ties by id; it may add units, which
  // start at the current time or later. Dependencies on units already
  // finished are met. Runs once per engine.
  Result run(const std::function<void(int unit)>& on_finish = {});

  // Registers a run's statistics: per resource (at its name) the amount
  // `used` and its `capacity` per second (utilisation, use per frame at
  // the frame rate over capacity, is a formula of the output:
  // run/result_metrics.h); per queue (at its name) `queue_busy`, the
  // seconds it had a unit running, work and latency.
  void report(const Result& r, Stats& out) const;

  // Rate allocations of the last run that stopped at the iteration limit
  // (ResourceSharing::unconverged).
  uint64_t unconverged() const { return m_unconverged; }

  // While running (from on_finish): the current time, whether a unit has
  // started or ended, and the fraction of its work still to do (1 before it
  // starts, 0 once its work is done).
  double now() const { return m_now; }
  bool started(int unit) const;
  bool finished(int unit) const;
  double work_left(int unit) const;

 private:
  enum class State : uint8_t { waiting, running, latency, done };
  void start(int i);
  void finish(int i, const std::function<void(int)>& on_finish);
  void start_ready();

  std::vector<std::string> m_resource_names, m_resource_units, m_queue_names;
  std::vector<double> m_capacity;
  std::vector<Unit> m_units;

  // Run state, grown as units are added.
  bool m_running_run = false;
  double m_now = 0;
  Result m_res;
  std::vector<State> m_state;
  std::vector<double> m_left;
  std::vector<int> m_deps;
  std::vector<std::vector<int>> m_dependents;
  std::vector<std::vector<int>> m_queue_units;
  std::vector<size_t> m_queue_head;
  std::vector<bool> m_queue_idle;
  std::vector<int> m_free_ready;     // units without a queue whose dependencies are met, not started
  std::vector<int> m_finished_work;  // scratch of run, kept between events
  std::vector<int> m_running;        // ids, ascending
  std::vector<std::pair<double, int>> m_in_latency;
  size_t m_done = 0;
  Sharing m_sharing = Sharing::fair;
  uint64_t m_unconverged = 0;
};

}  // namespace oovr
