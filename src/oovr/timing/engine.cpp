#include "oovr/timing/engine.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "oovr/core/error.h"

namespace oovr {

int TimingEngine::add_resource(std::string name, double capacity) {
  if (!(capacity > 0) || !std::isfinite(capacity))
    throw Error("timing: resource '" + name + "' needs a positive capacity");
  m_resource_names.push_back(std::move(name));
  m_capacity.push_back(capacity);
  return int(m_capacity.size()) - 1;
}

int TimingEngine::add_queue(std::string name) {
  m_queue_names.push_back(std::move(name));
  return int(m_queue_names.size()) - 1;
}

int TimingEngine::add_unit(Unit u) {
  const int id = int(m_units.size());
  if (u.queue >= int(m_queue_names.size())) throw Error("timing: unit " + std::to_string(id) + " names a missing queue");
  for (int d : u.after)
    if (d < 0 || d >= id) throw Error("timing: unit " + std::to_string(id) + " depends on a unit not added before it");
  for (auto& [r, amount] : u.demand)
    if (r < 0 || r >= int(m_capacity.size()) || !(amount >= 0) || !std::isfinite(amount))
      throw Error("timing: unit " + std::to_string(id) + " has a bad demand");
  if (!(u.latency >= 0)) throw Error("timing: unit " + std::to_string(id) + " has a negative latency");
  m_units.push_back(std::move(u));
  return id;
}

TimingEngine::Result TimingEngine::run() const {
  const size_t n = m_units.size();
  Result res;
  res.units.assign(n, {});
  res.queue_busy.assign(m_queue_names.size(), 0);
  res.resource_used.assign(m_capacity.size(), 0);

  enum class State : uint8_t { waiting, running, latency, done };
  std::vector<State> state(n, State::waiting);
  std::vector<double> left(n, 1.0);  // fraction of the work still to do
  std::vector<int> deps(n, 0);
  std::vector<std::vector<int>> dependents(n);
  std::vector<std::vector<int>> queue_units(m_queue_names.size());
  std::vector<size_t> queue_head(m_queue_names.size(), 0);
  std::vector<bool> queue_idle(m_queue_names.size(), true);
  for (size_t i = 0; i < n; ++i) {
    deps[i] = int(m_units[i].after.size());
    for (int d : m_units[i].after) dependents[size_t(d)].push_back(int(i));
    if (m_units[i].queue >= 0) queue_units[size_t(m_units[i].queue)].push_back(int(i));
  }

  std::vector<int> running;  // ids, ascending
  std::vector<std::pair<double, int>> in_latency;  // (finish, id)
  double t = 0;
  size_t done = 0;

  auto startable = [&](int i) {
    if (state[size_t(i)] != State::waiting || deps[size_t(i)] > 0) return false;
    const int q = m_units[size_t(i)].queue;
    return q < 0 || (queue_idle[size_t(q)] && queue_units[size_t(q)][queue_head[size_t(q)]] == i);
  };
  auto start = [&](int i) {
    state[size_t(i)] = State::running;
    res.units[size_t(i)].start = t;
    const int q = m_units[size_t(i)].queue;
    if (q >= 0) queue_idle[size_t(q)] = false;
    running.insert(std::upper_bound(running.begin(), running.end(), i), i);
  };
  auto start_all = [&] {
    // Units without a queue, and the head of every idle queue.
    for (size_t i = 0; i < n; ++i)
      if (m_units[i].queue < 0 && startable(int(i))) start(int(i));
    for (size_t q = 0; q < queue_units.size(); ++q)
      if (queue_idle[q] && queue_head[q] < queue_units[q].size() && startable(queue_units[q][queue_head[q]]))
        start(queue_units[q][queue_head[q]]);
  };
  auto finish = [&](int i) {
    state[size_t(i)] = State::done;
    res.units[size_t(i)].finish = t;
    res.makespan = std::max(res.makespan, t);
    ++done;
    const int q = m_units[size_t(i)].queue;
    if (q >= 0) {
      queue_idle[size_t(q)] = true;
      ++queue_head[size_t(q)];
      res.queue_busy[size_t(q)] += t - res.units[size_t(i)].start;
    }
    for (int d : dependents[size_t(i)]) --deps[size_t(d)];
  };

  start_all();
  std::vector<double> share(m_capacity.size());
  std::vector<int> users(m_capacity.size());
  std::vector<double> rate;
  while (done < n) {
    // Rates: equal shares of every resource among the units using it.
    std::fill(users.begin(), users.end(), 0);
    for (int i : running)
      for (const auto& [r, amount] : m_units[size_t(i)].demand)
        if (amount > 0) ++users[size_t(r)];
    for (size_t r = 0; r < share.size(); ++r) share[r] = users[r] ? m_capacity[r] / users[r] : 0;
    rate.assign(running.size(), std::numeric_limits<double>::infinity());
    double step = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < running.size(); ++k) {
      for (const auto& [r, amount] : m_units[size_t(running[k])].demand)
        if (amount > 0) rate[k] = std::min(rate[k], share[size_t(r)] / amount);
      step = std::min(step, std::isinf(rate[k]) ? 0.0 : left[size_t(running[k])] / rate[k]);
    }
    double next_latency = std::numeric_limits<double>::infinity();
    for (const auto& [f, id] : in_latency) next_latency = std::min(next_latency, f);
    if (running.empty() && in_latency.empty())
      throw Error("timing: units wait on each other and can never start (a dependency cycle or an empty queue head)");
    const double t_next = std::min(t + step, next_latency);
    const double dt = t_next - t;
    // Advance the running units; those whose work ends at t_next move on.
    // (A latency phase ending first is an event of its own.)
    const bool work_event = t + step <= next_latency;
    std::vector<int> finished_work;
    for (size_t k = 0; k < running.size(); ++k) {
      const int i = running[k];
      const double to_finish = std::isinf(rate[k]) ? 0.0 : left[size_t(i)] / rate[k];
      const bool ends = work_event && to_finish <= step * (1 + 1e-12);
      const double progress = ends ? left[size_t(i)] : std::min(left[size_t(i)], rate[k] * dt);
      for (const auto& [r, amount] : m_units[size_t(i)].demand) res.resource_used[size_t(r)] += amount * progress;
      left[size_t(i)] -= progress;
      if (ends) {
        left[size_t(i)] = 0;
        finished_work.push_back(i);
      }
    }
    t = t_next;
    for (int i : finished_work) {
      running.erase(std::find(running.begin(), running.end(), i));
      res.units[size_t(i)].work_done = t;
      if (m_units[size_t(i)].latency > 0) {
        state[size_t(i)] = State::latency;
        in_latency.push_back({t + m_units[size_t(i)].latency, i});
      } else {
        finish(i);
      }
    }
    // Latency phases that end now (in id order for determinism).
    std::sort(in_latency.begin(), in_latency.end(), [](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && a.second < b.second);
    });
    while (!in_latency.empty() && in_latency.front().first <= t) {
      const int i = in_latency.front().second;
      in_latency.erase(in_latency.begin());
      finish(i);
    }
    start_all();
  }
  return res;
}

}  // namespace oovr
