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

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace oovr {

enum class Sharing : uint8_t { fair, equal };

using Demand = std::vector<std::pair<int, double>>;  // (resource, amount) pairs

// Sharing problems solved before, and the levels they settled at, for
// ResourceSharing to reuse (rates()). One engine's run keeps its own: a
// frame's replay meets a few thousand problems, a third of them again.
// (Kept across a window's frames instead, for the measured pass to meet
// its warm-up's, it measured the same.)
class SolvedSharing {
 public:
  // The most problems kept, and words of their keys and levels (32 MB);
  // past either the kept ones are dropped.
  static constexpr std::size_t kKept = 1u << 14, kKeptWords = 1u << 22;
  // Problems found solved before (their levels reused), and solved by
  // iterating.
  uint64_t reused() const { return m_reused; }
  uint64_t solved() const { return m_solved_count; }

 private:
  friend class ResourceSharing;
  struct Solved {
    uint64_t hash = 0;
    uint32_t at = 0, words = 0;  // the key in m_words; its levels follow it
    bool converged = true;
  };
  // The problem `key` (of hash `hash`) solved before, or null.
  const Solved* find(const std::vector<uint64_t>& key, uint64_t hash);
  // Keeps `levels` (as bits) as the solution of `key`.
  void keep(const std::vector<uint64_t>& key, uint64_t hash, const std::vector<uint64_t>& levels, bool converged);

  // The problems' keys and levels one after the other in m_words, found by
  // open addressing in m_slots (an entry's index + 1; 0: empty).
  std::vector<Solved> m_solved;
  std::vector<uint64_t> m_words;
  std::vector<uint32_t> m_slots;
  uint64_t m_reused = 0, m_solved_count = 0;
};

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
  // Problems whose iteration's every step was known from its first
  // (settle()), so that it did not step again; and those where some of
  // its resources' steps were.
  uint64_t settled() const { return m_settled; }
  uint64_t partly_settled() const { return m_partly_settled; }
  const SolvedSharing& problems() const { return m_solved; }

 private:
  // One step of the fixed-point iteration on the shared resources: the
  // water level each would settle at given the others' levels `in`.
  void step(const std::vector<double>& in, std::vector<double>& out);
  // Lists in m_moving the shared resources whose step at some levels
  // between `at` and the capacities may differ from their level at `at`
  // (a sufficient test: the others' steps there give their `at`, bit for
  // bit), and in m_watch what their steps read.
  void settle(const std::vector<double>& at);
  // step() for the resources in m_moving only.
  void step_moving(const std::vector<double>& in, std::vector<double>& out);
  // Per unit, its smallest and second smallest L_r / a_ir over the shared
  // resources, and on which resource the smallest is (m_best, m_best_resource).
  void best_levels(const std::vector<double>& in);
  // Keeps v = L_r / a_kr among unit k's smallest two (best_levels()).
  void note_level(int k, int r, double v) {
    double& b1 = m_best[2 * size_t(k)];
    double& b2 = m_best[2 * size_t(k) + 1];
    if (v < b1) {
      b2 = b1;
      b1 = v;
      m_best_resource[size_t(k)] = r;
    } else if (v < b2) {
      b2 = v;
    }
  }
  // What unit k's other shared resources let it run at (best_levels()'s).
  double other(int k, int r) const { return m_best_resource[size_t(k)] == r ? m_best[2 * size_t(k) + 1] : m_best[2 * size_t(k)]; }
  // Unit k's demand on r (of amount a): a times what its other shared
  // resources and its own limit let it run at.
  double demand(int k, int r, double a) const { return a * std::min(other(k, r), m_own[size_t(k)]); }
  // The water level of each of `resources` given best_levels()'s, in `out`.
  void water_levels(const std::vector<int>& resources, std::vector<double>& out);

  // The shared resources' problem, as the words that decide the
  // iteration's every step (rates()); returns its hash.
  uint64_t make_key();

  std::vector<double> m_capacity;
  uint64_t m_unconverged = 0, m_iterations = 0, m_settled = 0, m_partly_settled = 0;
  SolvedSharing m_solved;
  std::vector<uint64_t> m_key, m_levels;
  std::vector<int> m_label;  // per unit: its number among the shared resources' users (-1: none)
  // Scratch, kept between calls.
  std::vector<std::vector<std::pair<int, double>>> m_users;  // per resource: (unit, amount)
  std::vector<int> m_used;                                   // resources with users, ascending
  std::vector<uint64_t> m_in_use;                            // the same as bits, while they are listed
  std::vector<int> m_shared;                                 // resources with two users or more
  std::vector<double> m_rate, m_own, m_level, m_next, m_best, m_demands, m_usage;
  std::vector<int> m_best_resource;
  // settle(): the users' demands at the capacities, and (demand, whether
  // it may rise) per user of one resource.
  std::vector<double> m_top;
  std::vector<std::pair<double, bool>> m_flagged;
  // settle()'s answer: the resources still stepped, the first step's
  // levels (per shared resource), and their steps' reads.
  std::vector<int> m_moving;
  std::vector<double> m_first;
  struct Watch {
    int resource, unit;
    double amount;
  };
  std::vector<Watch> m_watch;
  std::vector<int> m_watched;         // the units in m_watch
  std::vector<uint8_t> m_is_watched;  // per unit
};

}  // namespace oovr
