#include "oovr/timing/sharing.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>
#include <utility>

#include "oovr/core/rng.h"

namespace oovr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The water line of demands sorted by `value`: the index of the first one
// above the share left and that share, or (all of them, `capacity`) when
// they fit.
template <class Demand, class Value>
std::pair<size_t, double> water_line(std::span<const Demand> sorted, double capacity, Value value) {
  double left = capacity;
  const size_t n = sorted.size();
  for (size_t i = 0; i < n; ++i) {
    const double share = left / double(n - i);
    if (value(sorted[i]) > share) return {i, share};
    left -= value(sorted[i]);
  }
  return {n, capacity};
}

// The water level at which users with these demands share `capacity`: each
// gets min(demand, level) and together they use all of it; `capacity` (no
// one can use more) when the demands fit. Sorts `demands`.
double water_level(std::span<double> demands, double capacity) {
  // Sorted by insertion, in place: most problems' resources have two or
  // three users (of 2.2 million water levels in OO-VR's replay of 8 frames
  // of oa:oa_dm4, 1.9 million had two or three, none over 13), where
  // std::sort's calls and moves cost more than the comparisons. Any sort
  // gives the same values in the same order (the demands are never NaN),
  // so the same bits; a resource of many users (a link of a large machine)
  // keeps std::sort, whose time does not grow with their square.
  double* d = demands.data();
  const size_t n = demands.size();
  if (n > 16) {
    std::sort(demands.begin(), demands.end());
  } else {
    for (size_t i = 1; i < n; ++i) {
      const double v = d[i];
      size_t j = i;
      for (; j > 0 && v < d[j - 1]; --j) d[j] = d[j - 1];
      d[j] = v;
    }
  }
  return water_line(std::span<const double>(demands), capacity, [](double x) { return x; }).second;
}

// Sorts (demand, flag) pairs by demand and returns how many of them lie
// below the water line, as water_level() finds it.
size_t below_line(std::vector<std::pair<double, bool>>& demands, double capacity) {
  std::sort(demands.begin(), demands.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  return water_line(std::span<const std::pair<double, bool>>(demands), capacity, [](const auto& d) { return d.first; }).first;
}

}  // namespace

void ResourceSharing::best_levels(const std::vector<double>& in) {
  // Per unit, the smallest and second smallest of L_r / a_ir over its
  // shared resources: with its own limit, what its other resources let it
  // run at, for each of them (other()).
  const size_t m = m_rate.size();
  m_best.assign(2 * m, kInf);
  m_best_resource.assign(m, -1);
  for (int r : m_shared)
    for (const auto& [k, a] : m_users[size_t(r)]) note_level(k, r, in[size_t(r)] / a);
}

void ResourceSharing::water_levels(const std::vector<int>& resources, std::vector<double>& out) {
  // The demands written in place (the scratch list only grows).
  for (int r : resources) {
    const auto& users = m_users[size_t(r)];
    if (m_demands.size() < users.size()) m_demands.resize(users.size());
    double* d = m_demands.data();
    for (const auto& [k, a] : users) *d++ = demand(k, r, a);
    out[size_t(r)] = water_level(std::span<double>(m_demands.data(), users.size()), m_capacity[size_t(r)]);
  }
}

void ResourceSharing::step(const std::vector<double>& in, std::vector<double>& out) {
  best_levels(in);
  water_levels(m_shared, out);
}

void ResourceSharing::settle(const std::vector<double>& at) {
  // The iteration's levels L lie between `at` (the first step's levels,
  // each at most its capacity) and the capacities while every resource's
  // step gives its level there a value in that range: always for the
  // settled ones (below), checked at each step for the others (rates()). A
  // user's demand, a * min(other, own), does not fall as the levels rise
  // (division, multiplication and min round monotonically): on that range
  // it lies between its values at the two ends, and is fixed where they
  // are the same. A resource's step is the same on the whole range when
  // - its users' demands at the capacities, the largest they can be, all
  //   fit: with smaller ones every share water_level() compares them with
  //   is no smaller, so all still fit and it returns the capacity; or
  // - the demands below its water line at `at` are fixed and every demand
  //   that may change is above the largest of them: water_level() reads
  //   only the demands below the line (it returns at the first sorted
  //   demand above the share left), which are then the same values in the
  //   same order at every L in the range, and the first one above is no
  //   smaller, so it returns the same share.
  best_levels(m_capacity);
  m_top.clear();
  for (int r : m_shared)
    for (const auto& [k, a] : m_users[size_t(r)]) m_top.push_back(demand(k, r, a));
  best_levels(at);
  m_moving.clear();
  size_t u = 0;
  for (int r : m_shared) {
    const size_t n = m_users[size_t(r)].size();
    m_flagged.clear();
    for (size_t i = 0; i < n; ++i) m_flagged.push_back({m_top[u + i], false});
    if (below_line(m_flagged, m_capacity[size_t(r)]) == n) {
      u += n;
      continue;
    }
    m_flagged.clear();
    for (const auto& [k, a] : m_users[size_t(r)]) {
      const double d = demand(k, r, a);
      m_flagged.push_back({d, d != m_top[u++]});
    }
    const size_t below = below_line(m_flagged, m_capacity[size_t(r)]);
    if (below == 0) continue;
    const double line = m_flagged[below - 1].first;
    for (const auto& [demand, moves] : m_flagged)
      if (moves && !(demand > line)) {
        m_moving.push_back(r);
        break;
      }
  }
  // What the moving resources' steps read: their users' levels on every
  // shared resource, in step()'s order.
  m_watch.clear();
  m_watched.clear();
  if (m_moving.empty()) return;
  m_is_watched.assign(m_rate.size(), 0);
  for (int r : m_moving)
    for (const auto& [k, a] : m_users[size_t(r)])
      if (!m_is_watched[size_t(k)]) {
        m_is_watched[size_t(k)] = 1;
        m_watched.push_back(k);
      }
  for (int r : m_shared)
    for (const auto& [k, a] : m_users[size_t(r)])
      if (m_is_watched[size_t(k)]) m_watch.push_back({r, k, a});
}

void ResourceSharing::step_moving(const std::vector<double>& in, std::vector<double>& out) {
  // step()'s work for the moving resources only: the others' levels stay
  // the first step's (settle()).
  for (int k : m_watched) {
    m_best[2 * size_t(k)] = m_best[2 * size_t(k) + 1] = kInf;
    m_best_resource[size_t(k)] = -1;
  }
  for (const Watch& w : m_watch) note_level(w.unit, w.resource, in[size_t(w.resource)] / w.amount);
  water_levels(m_moving, out);
}

uint64_t ResourceSharing::make_key() {
  // What the iteration reads (step()): the shared resources in order, each
  // one's users in order with their amounts, and each user's own limit.
  // Users are numbered in their order of first appearance, so that which
  // resources a unit shares is kept while its index among the running
  // units is not: a unit that shares nothing (its every resource its own)
  // starting or ending leaves the problem as it was. The capacities belong
  // to the object.
  m_key.clear();
  m_label.assign(m_rate.size(), -1);
  int labels = 0;
  for (int r : m_shared) {
    const auto& users = m_users[size_t(r)];
    m_key.push_back(uint64_t(uint32_t(r)) << 32 | uint64_t(users.size()));
    for (const auto& [k, a] : users) {
      int& label = m_label[size_t(k)];
      if (label < 0) label = labels++;
      m_key.push_back(uint64_t(label));
      m_key.push_back(std::bit_cast<uint64_t>(a));
    }
  }
  const size_t owns = m_key.size();
  m_key.resize(owns + size_t(labels));
  for (size_t k = 0; k < m_label.size(); ++k)
    if (m_label[k] >= 0) m_key[owns + size_t(m_label[k])] = std::bit_cast<uint64_t>(m_own[k]);
  uint64_t h = m_key.size();
  for (uint64_t w : m_key) h = (h ^ w) * 0x9e3779b97f4a7c15ull, h ^= h >> 31;
  return mix64(h);
}

const SolvedSharing::Solved* SolvedSharing::find(const std::vector<uint64_t>& key, uint64_t hash) {
  if (!m_slots.empty()) {
    const size_t mask = m_slots.size() - 1;
    for (size_t i = size_t(hash) & mask; m_slots[i]; i = (i + 1) & mask) {
      const Solved& s = m_solved[m_slots[i] - 1];
      if (s.hash == hash && s.words == key.size() && std::equal(key.begin(), key.end(), m_words.begin() + s.at)) {
        ++m_reused;
        return &s;
      }
    }
  }
  ++m_solved_count;
  return nullptr;
}

void SolvedSharing::keep(const std::vector<uint64_t>& key, uint64_t hash, const std::vector<uint64_t>& levels, bool converged) {
  if (m_solved.size() >= kKept || m_words.size() + key.size() + levels.size() > kKeptWords) {
    m_solved.clear();
    m_words.clear();
    std::fill(m_slots.begin(), m_slots.end(), 0);
  }
  // At most half the slots in use: probes stay short.
  if (2 * (m_solved.size() + 1) > m_slots.size()) {
    m_slots.assign(std::max<size_t>(64, 2 * m_slots.size()), 0);
    const size_t mask = m_slots.size() - 1;
    for (size_t e = 0; e < m_solved.size(); ++e) {
      size_t i = size_t(m_solved[e].hash) & mask;
      while (m_slots[i]) i = (i + 1) & mask;
      m_slots[i] = uint32_t(e + 1);
    }
  }
  m_solved.push_back({hash, uint32_t(m_words.size()), uint32_t(key.size()), converged});
  m_words.insert(m_words.end(), key.begin(), key.end());
  m_words.insert(m_words.end(), levels.begin(), levels.end());
  const size_t mask = m_slots.size() - 1;
  size_t i = size_t(hash) & mask;
  while (m_slots[i]) i = (i + 1) & mask;
  m_slots[i] = uint32_t(m_solved.size());
}

const std::vector<double>& ResourceSharing::rates(const std::vector<const Demand*>& demands, Sharing sharing) {
  const size_t m = demands.size();
  m_rate.assign(m, kInf);
  m_users.resize(m_capacity.size());
  m_in_use.resize((m_capacity.size() + 63) / 64);
  for (int r : m_used) m_users[size_t(r)].clear();
  m_used.clear();
  // The resources in use, in ascending order: marked in a bit set as their
  // first user appears, then read out word by word (a sort at every event
  // was 1% of the paper's sweep).
  for (size_t k = 0; k < m; ++k)
    for (const auto& [r, amount] : *demands[k])
      if (amount > 0) {
        if (m_users[size_t(r)].empty()) m_in_use[size_t(r) / 64] |= uint64_t(1) << (r % 64);
        m_users[size_t(r)].push_back({int(k), amount});
      }
  for (size_t w = 0; w < m_in_use.size(); ++w)
    for (uint64_t bits = std::exchange(m_in_use[w], 0); bits; bits &= bits - 1)
      m_used.push_back(int(w * 64) + std::countr_zero(bits));
  if (sharing == Sharing::equal) {
    for (int r : m_used) {
      const double share = m_capacity[size_t(r)] / double(m_users[size_t(r)].size());
      for (const auto& [k, a] : m_users[size_t(r)]) m_rate[size_t(k)] = std::min(m_rate[size_t(k)], share / a);
    }
    return m_rate;
  }
  // A resource with one user only limits that unit: its own limit.
  m_own.assign(m, kInf);
  m_shared.clear();
  for (int r : m_used) {
    if (m_users[size_t(r)].size() > 1) {
      m_shared.push_back(r);
      continue;
    }
    const auto& [k, a] = m_users[size_t(r)].front();
    m_own[size_t(k)] = std::min(m_own[size_t(k)], m_capacity[size_t(r)] / a);
  }
  // The levels of the shared resources: a damped fixed-point iteration from
  // every level at its capacity (the step alone may alternate around the
  // fixed point; half steps settle on it), to 1e-13 of each capacity.
  m_level.assign(m_capacity.size(), 0);
  m_next.assign(m_capacity.size(), 0);
  // The levels depend on nothing but the capacities and the words of
  // make_key(): a problem met before (an event that started or ended a unit
  // sharing nothing, the running units coming back to a mix they had)
  // takes the levels it settled at then, the same bits the iteration would
  // give again.
  bool converged = m_shared.empty();
  if (!converged) {
    const uint64_t hash = make_key();
    if (const SolvedSharing::Solved* solved = m_solved.find(m_key, hash)) {
      const uint64_t* levels = &m_solved.m_words[solved->at + solved->words];
      for (size_t j = 0; j < m_shared.size(); ++j) m_level[size_t(m_shared[j])] = std::bit_cast<double>(levels[j]);
      if (!solved->converged) ++m_unconverged;
    } else {
      for (int r : m_shared) m_level[size_t(r)] = m_capacity[size_t(r)];
      // After the first step, the resources whose every later step would
      // give its levels again (settle()) are not stepped again: the
      // iteration's halving goes on towards their levels, and the others'
      // steps read the levels as before. While every level stays between
      // the first step's and its capacity, which holds for the settled
      // ones and is checked for the others, the steps left out are known;
      // past it (met in no run measured) every resource is stepped again.
      // Half of the problems OO-VR's runs iterate on oa:oa_dm4 settle on
      // every resource (19,411 of 37,611: each resource's users bound
      // elsewhere, by its share alone, or all fitting), and the others on
      // three resources in four.
      enum class Steps { all, moving, none } steps = Steps::all;
      // Whether a level left the range between its first step and its
      // capacity at the last iteration's end (read while Steps::moving).
      bool left = false;
      for (int i = 0; i < 1000 && !converged; ++i) {
        ++m_iterations;
        if (steps == Steps::moving && left) steps = Steps::all;
        if (steps == Steps::moving) {
          step_moving(m_level, m_next);
        } else if (steps == Steps::all) {
          step(m_level, m_next);
          if (i == 0) {
            settle(m_next);
            m_first.clear();
            for (int r : m_shared) m_first.push_back(m_next[size_t(r)]);
            steps = m_moving.empty() ? Steps::none : Steps::moving;
            ++(m_moving.empty() ? m_settled : m_partly_settled);
            if (steps == Steps::none) {
              // No step moves again: the iteration would only halve each
              // level's distance to its first step's value n (at most its
              // capacity c, settle()) until all are within 1e-13 c, and then
              // take the values n. Each halving, fl(l + n) / 2, leaves at
              // most half the distance plus c 2^-53, so that happens within
              // 50 iterations, well before the limit: the levels are n.
              for (int r : m_shared) m_level[size_t(r)] = m_next[size_t(r)];
              converged = true;
              break;
            }
          }
        }
        // One pass: whether every level is within the tolerance of its
        // step, each level halved towards its step, and whether one left
        // the range (m_first holds the first step's levels from the first
        // iteration on). Converged, every level takes its step instead of
        // the halves. (Three passes were 4% of a replay's instructions.)
        converged = true;
        left = false;
        for (size_t j = 0; j < m_shared.size(); ++j) {
          const size_t r = size_t(m_shared[j]);
          const double l = m_level[r], n = m_next[r], c = m_capacity[r];
          if (std::abs(n - l) > 1e-13 * c) converged = false;
          const double half = 0.5 * (l + n);
          m_level[r] = half;
          if (!(half >= m_first[j] && half <= c)) left = true;
        }
        if (converged)
          for (int r : m_shared) m_level[size_t(r)] = m_next[size_t(r)];
      }
      if (!converged) ++m_unconverged;
      m_levels.clear();
      for (int r : m_shared) m_levels.push_back(std::bit_cast<uint64_t>(m_level[size_t(r)]));
      m_solved.keep(m_key, hash, m_levels, converged);
    }
  }
  for (size_t k = 0; k < m; ++k) m_rate[k] = m_own[k];
  for (int r : m_shared)
    for (const auto& [k, a] : m_users[size_t(r)]) m_rate[size_t(k)] = std::min(m_rate[size_t(k)], m_level[size_t(r)] / a);
  // What is left of the tolerance (or of an unconverged iteration) never
  // asks a resource for more than it has.
  for (int r : m_shared) {
    double used = 0;
    for (const auto& [k, a] : m_users[size_t(r)]) used += a * m_rate[size_t(k)];
    if (used > m_capacity[size_t(r)]) {
      const double scale = m_capacity[size_t(r)] / used;
      for (const auto& [k, a] : m_users[size_t(r)]) m_rate[size_t(k)] *= scale;
    }
  }
  return m_rate;
}

}  // namespace oovr
