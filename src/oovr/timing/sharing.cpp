#include "oovr/timing/sharing.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace oovr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The water level at which users with these demands share `capacity`: each
// gets min(demand, level) and together they use all of it; `capacity` (no
// one can use more) when the demands fit. Sorts `demands`.
double water_level(std::vector<double>& demands, double capacity) {
  std::sort(demands.begin(), demands.end());
  double left = capacity;
  const size_t n = demands.size();
  for (size_t i = 0; i < n; ++i) {
    const double share = left / double(n - i);
    if (demands[i] > share) return share;
    left -= demands[i];
  }
  return capacity;
}

}  // namespace

void ResourceSharing::step(const std::vector<double>& in, std::vector<double>& out) {
  // Per unit, the smallest and second smallest of L_r / a_ir over its
  // shared resources, and its own limit: what its other resources let it
  // run at, for each of them.
  const size_t m = m_rate.size();
  m_best.assign(2 * m, kInf);
  m_best_resource.assign(m, -1);
  for (int r : m_shared)
    for (const auto& [k, a] : m_users[size_t(r)]) {
      const double v = in[size_t(r)] / a;
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
  for (int r : m_shared) {
    m_demands.clear();
    for (const auto& [k, a] : m_users[size_t(r)]) {
      const double other = m_best_resource[size_t(k)] == r ? m_best[2 * size_t(k) + 1] : m_best[2 * size_t(k)];
      m_demands.push_back(a * std::min(other, m_own[size_t(k)]));
    }
    out[size_t(r)] = water_level(m_demands, m_capacity[size_t(r)]);
  }
}

const std::vector<double>& ResourceSharing::rates(const std::vector<const Demand*>& demands, Sharing sharing) {
  const size_t m = demands.size();
  m_rate.assign(m, kInf);
  m_users.resize(m_capacity.size());
  for (int r : m_used) m_users[size_t(r)].clear();
  m_used.clear();
  for (size_t k = 0; k < m; ++k)
    for (const auto& [r, amount] : *demands[k])
      if (amount > 0) {
        if (m_users[size_t(r)].empty()) m_used.push_back(r);
        m_users[size_t(r)].push_back({int(k), amount});
      }
  std::sort(m_used.begin(), m_used.end());
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
  for (int r : m_shared) m_level[size_t(r)] = m_capacity[size_t(r)];
  bool converged = m_shared.empty();
  for (int i = 0; i < 1000 && !converged; ++i) {
    ++m_iterations;
    step(m_level, m_next);
    converged = true;
    for (int r : m_shared)
      if (std::abs(m_next[size_t(r)] - m_level[size_t(r)]) > 1e-13 * m_capacity[size_t(r)]) converged = false;
    for (int r : m_shared) m_level[size_t(r)] = converged ? m_next[size_t(r)] : 0.5 * (m_level[size_t(r)] + m_next[size_t(r)]);
  }
  if (!converged) ++m_unconverged;
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
