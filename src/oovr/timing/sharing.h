// How running work units share resources (DESIGN.md, "How work becomes
// time"): every unit progresses at one rate, a fraction of its work per
// second, the same for all it demands; the rates must fit every resource's
// capacity.
//
// `fair` (the default) is max-min fair and work-conserving per resource, as
// round-robin arbitration of a link, a DRAM or the ROPs behaves: what a unit
// cannot use because something else limits it goes to the others. The rates
// are the fixed point where every resource r has a level L_r (infinite when
// r has capacity to spare) and every unit i runs at min_r L_r / a_ir (a_ir:
// its demand of r); a saturated resource's level is its water level: each
// user gets what its other resources let it use, capped at the level, and
// together the users use the whole capacity. Every unit then has a
// bottleneck: a full resource on which no other user gets more than it.
//
// `equal` splits every resource equally among its users and loses the shares
// a user cannot use: oovr's model before work conservation, kept so that
// what it changes can be measured (`timing.sharing`).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace oovr {

enum class Sharing : uint8_t { fair, equal };

using Demand = std::vector<std::pair<int, double>>;  // (resource, amount) pairs

class ResourceSharing {
 public:
  explicit ResourceSharing(std::vector<double> capacity) : m_capacity(std::move(capacity)) {}

  // Rates of units with these demands (amounts <= 0 are ignored; a unit
  // demanding nothing gets an infinite rate). Deterministic: the same
  // inputs give the same rates.
  const std::vector<double>& rates(const std::vector<const Demand*>& demands, Sharing sharing);

  // Allocations that reached the iteration limit before converging (their
  // rates fit the capacities but may leave some unused); 0 in every case
  // measured so far.
  uint64_t unconverged() const { return m_unconverged; }
  // Fixed-point iterations over all allocations, for profiling.
  uint64_t iterations() const { return m_iterations; }

 private:
  // One step of the fixed-point iteration on the shared resources: the
  // water level each would settle at given the others' levels `in`.
  void step(const std::vector<double>& in, std::vector<double>& out);

  std::vector<double> m_capacity;
  uint64_t m_unconverged = 0, m_iterations = 0;
  // Scratch, kept between calls.
  std::vector<std::vector<std::pair<int, double>>> m_users;  // per resource: (unit, amount)
  std::vector<int> m_used;                                   // resources with users, ascending
  std::vector<int> m_shared;                                 // resources with two users or more
  std::vector<double> m_rate, m_own, m_level, m_next, m_best, m_demands, m_usage;
  std::vector<int> m_best_resource;
};

}  // namespace oovr
