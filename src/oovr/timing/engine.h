// The event-driven timing engine (DESIGN.md, "How work becomes time").
//
// Work units demand amounts of resources (shader instructions, texture
// samples, ROP pixels, DRAM bytes, link bytes, ...); each resource has a
// capacity per second. Units in one queue (a GPM's pipeline) run one after
// another; units of different queues run at the same time and share every
// resource they both use. A fluid model decides how fast each runs:
//
//   every resource's capacity is split equally among the running units that
//   demand it; a unit progresses at the pace of its bottleneck, the resource
//   whose share it would take longest to get through.
//
// Between two events (a unit starting or finishing) every rate is constant,
// so the engine jumps from event to event. A unit's latency (DRAM, link
// hops) is added after its work, without holding resources; its queue's next
// unit starts only after it. Ties are broken by unit id: the result is the
// same on every run and for any thread count.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace oovr {

class TimingEngine {
 public:
  struct Unit {
    int queue = -1;                             // -1: runs as soon as its dependencies allow
    std::vector<std::pair<int, double>> demand;  // (resource, amount)
    double latency = 0;                          // seconds added after the work
    std::vector<int> after;                      // units that must finish first
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

  // Adds a resource with `capacity` units per second; returns its id.
  int add_resource(std::string name, double capacity);
  int add_queue(std::string name);
  // Adds a unit; its dependencies must be units added before. Returns its id.
  int add_unit(Unit u);

  const std::string& resource_name(int r) const { return m_resource_names[size_t(r)]; }
  double capacity(int r) const { return m_capacity[size_t(r)]; }
  size_t resources() const { return m_capacity.size(); }
  size_t queues() const { return m_queue_names.size(); }
  size_t units() const { return m_units.size(); }

  Result run() const;

 private:
  std::vector<std::string> m_resource_names, m_queue_names;
  std::vector<double> m_capacity;
  std::vector<Unit> m_units;
};

}  // namespace oovr
