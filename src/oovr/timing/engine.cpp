#include "oovr/timing/engine.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "oovr/core/error.h"

namespace oovr {

int TimingEngine::add_resource(std::string name, double capacity, std::string unit) {
  if (!(capacity > 0) || !std::isfinite(capacity)) throw Error("timing: resource '" + name + "' needs a positive capacity");
  m_resource_names.push_back(std::move(name));
  m_resource_units.push_back(std::move(unit));
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
  if (m_running_run) {
    // Joins the run in progress: only unfinished dependencies count.
    const Unit& v = m_units.back();
    m_res.units.push_back({});
    m_state.push_back(State::waiting);
    m_left.push_back(1.0);
    m_dependents.emplace_back();
    int deps = 0;
    for (int d : v.after)
      if (m_state[size_t(d)] != State::done) {
        ++deps;
        m_dependents[size_t(d)].push_back(id);
      }
    m_deps.push_back(deps);
    if (v.queue >= 0) m_queue_units[size_t(v.queue)].push_back(id);
    else if (deps == 0) m_free_ready.push_back(id);
  }
  return id;
}

bool TimingEngine::started(int unit) const {
  return m_running_run && size_t(unit) < m_state.size() && m_state[size_t(unit)] != State::waiting;
}

bool TimingEngine::finished(int unit) const {
  return m_running_run && size_t(unit) < m_state.size() && m_state[size_t(unit)] == State::done;
}

double TimingEngine::work_left(int unit) const {
  if (!m_running_run || size_t(unit) >= m_left.size()) return 1.0;
  return m_left[size_t(unit)];
}

void TimingEngine::start(int i) {
  m_state[size_t(i)] = State::running;
  m_res.units[size_t(i)].start = m_now;
  const int q = m_units[size_t(i)].queue;
  if (q >= 0) m_queue_idle[size_t(q)] = false;
  m_running.insert(std::upper_bound(m_running.begin(), m_running.end(), i), i);
}

void TimingEngine::start_ready() {
  // Units without a queue whose dependencies are met (finish() lists them
  // as their last dependency ends, so that waiting ones are not scanned at
  // every event: a frame's composition adds hundreds), and the head of
  // every idle queue. The order they start in does not matter: the running
  // units are kept in id order.
  for (int i : m_free_ready) start(i);
  m_free_ready.clear();
  for (size_t q = 0; q < m_queue_units.size(); ++q)
    if (m_queue_idle[q] && m_queue_head[q] < m_queue_units[q].size()) {
      const int i = m_queue_units[q][m_queue_head[q]];
      if (m_state[size_t(i)] == State::waiting && m_deps[size_t(i)] == 0) start(i);
    }
}

void TimingEngine::finish(int i, const std::function<void(int)>& on_finish) {
  m_state[size_t(i)] = State::done;
  m_res.units[size_t(i)].finish = m_now;
  m_res.makespan = std::max(m_res.makespan, m_now);
  ++m_done;
  const int q = m_units[size_t(i)].queue;
  if (q >= 0) {
    m_queue_idle[size_t(q)] = true;
    ++m_queue_head[size_t(q)];
    m_res.queue_busy[size_t(q)] += m_now - m_res.units[size_t(i)].start;
  }
  for (int d : m_dependents[size_t(i)])
    if (--m_deps[size_t(d)] == 0 && m_units[size_t(d)].queue < 0) m_free_ready.push_back(d);
  if (on_finish) on_finish(i);
}

TimingEngine::Result TimingEngine::run(const std::function<void(int)>& on_finish) {
  if (m_running_run) throw Error("timing: an engine runs once");
  const size_t n = m_units.size();
  m_running_run = true;
  m_now = 0;
  m_res = Result{};
  m_res.units.assign(n, {});
  m_res.queue_busy.assign(m_queue_names.size(), 0);
  m_res.resource_used.assign(m_capacity.size(), 0);
  m_state.assign(n, State::waiting);
  m_left.assign(n, 1.0);
  m_deps.assign(n, 0);
  m_dependents.assign(n, {});
  m_queue_units.assign(m_queue_names.size(), {});
  m_queue_head.assign(m_queue_names.size(), 0);
  m_queue_idle.assign(m_queue_names.size(), true);
  // Each list sized once (counted first): grown entry by entry, they were
  // a chain of allocations per unit.
  {
    std::vector<uint32_t> dependents(n, 0), in_queue(m_queue_names.size(), 0);
    for (size_t i = 0; i < n; ++i) {
      for (int d : m_units[i].after) ++dependents[size_t(d)];
      if (m_units[i].queue >= 0) ++in_queue[size_t(m_units[i].queue)];
    }
    for (size_t i = 0; i < n; ++i)
      if (dependents[i]) m_dependents[i].reserve(dependents[i]);
    for (size_t q = 0; q < in_queue.size(); ++q) m_queue_units[q].reserve(in_queue[q]);
  }
  for (size_t i = 0; i < n; ++i) {
    m_deps[i] = int(m_units[i].after.size());
    for (int d : m_units[i].after) m_dependents[size_t(d)].push_back(int(i));
    if (m_units[i].queue >= 0) m_queue_units[size_t(m_units[i].queue)].push_back(int(i));
    else if (m_deps[i] == 0) m_free_ready.push_back(int(i));
  }

  start_ready();
  ResourceSharing sharing(m_capacity);
  std::vector<const Demand*> demands;
  while (m_done < m_units.size()) {
    demands.clear();
    for (int i : m_running) demands.push_back(&m_units[size_t(i)].demand);
    const std::vector<double>& rate = sharing.rates(demands, m_sharing);
    double step = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < m_running.size(); ++k)
      step = std::min(step, std::isinf(rate[k]) ? 0.0 : m_left[size_t(m_running[k])] / rate[k]);
    double next_latency = std::numeric_limits<double>::infinity();
    for (const auto& [f, id] : m_in_latency) next_latency = std::min(next_latency, f);
    if (m_running.empty() && m_in_latency.empty())
      throw Error("timing: units wait on each other and can never start (a dependency cycle or an empty queue head)");
    const double t_next = std::min(m_now + step, next_latency);
    const double dt = t_next - m_now;
    // Advance the running units; those whose work ends at t_next move on.
    // (A latency phase ending first is an event of its own.)
    const bool work_event = m_now + step <= next_latency;
    std::vector<int>& finished_work = m_finished_work;
    finished_work.clear();
    for (size_t k = 0; k < m_running.size(); ++k) {
      const int i = m_running[k];
      const double to_finish = std::isinf(rate[k]) ? 0.0 : m_left[size_t(i)] / rate[k];
      const bool ends = work_event && to_finish <= step * (1 + 1e-12);
      const double progress = ends ? m_left[size_t(i)] : std::min(m_left[size_t(i)], rate[k] * dt);
      for (const auto& [r, amount] : m_units[size_t(i)].demand) m_res.resource_used[size_t(r)] += amount * progress;
      m_left[size_t(i)] -= progress;
      if (ends) {
        m_left[size_t(i)] = 0;
        finished_work.push_back(i);
      }
    }
    m_now = t_next;
    for (int i : finished_work) {
      m_running.erase(std::find(m_running.begin(), m_running.end(), i));
      m_res.units[size_t(i)].work_done = m_now;
      if (m_units[size_t(i)].latency > 0) {
        m_state[size_t(i)] = State::latency;
        m_in_latency.push_back({m_now + m_units[size_t(i)].latency, i});
      } else {
        finish(i, on_finish);
      }
    }
    // Latency phases that end now (in id order for determinism).
    std::sort(m_in_latency.begin(), m_in_latency.end(),
              [](const auto& a, const auto& b) { return a.first < b.first || (a.first == b.first && a.second < b.second); });
    while (!m_in_latency.empty() && m_in_latency.front().first <= m_now) {
      const int i = m_in_latency.front().second;
      m_in_latency.erase(m_in_latency.begin());
      finish(i, on_finish);
    }
    start_ready();
  }
  m_unconverged = sharing.unconverged();
  return m_res;
}

void TimingEngine::report(const Result& r, Stats& out) const {
  for (size_t k = 0; k < m_capacity.size(); ++k) {
    const std::string& unit = m_resource_units[k];
    const double used = k < r.resource_used.size() ? r.resource_used[k] : 0;
    out.add(m_resource_names[k], "used", used, unit, Merge::sum);
    // Per second: bytes per second, a count per second, or (time held per
    // second) a count of holders.
    out.add(m_resource_names[k], "capacity", m_capacity[k], unit == "s" ? "" : unit.empty() ? "1/s" : unit + "/s", Merge::max);
  }
  for (size_t q = 0; q < m_queue_names.size(); ++q)
    out.add(m_queue_names[q], "queue_busy", q < r.queue_busy.size() ? r.queue_busy[q] : 0, "s", Merge::mean);
}

}  // namespace oovr
