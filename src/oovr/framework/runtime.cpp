#include "oovr/framework/runtime.h"

#include <algorithm>
#include <string>

#include "oovr/core/error.h"

namespace oovr {

OORuntime::OORuntime(const OOSpec& spec, int gpms, std::vector<Batch> batches,
                     const std::vector<std::vector<const TileWork*>>& records, const std::vector<uint64_t>& vertices,
                     RuntimeExecutor& executor, std::optional<Rates> rates, std::vector<std::vector<double>> link_seconds)
    : m_spec(spec), m_n(gpms), m_exec(executor), m_batches_in(std::move(batches)), m_link_seconds(std::move(link_seconds)) {
  if (!m_link_seconds.empty() && m_link_seconds.size() != records.size())
    throw Error("OO runtime: link costs for " + std::to_string(m_link_seconds.size()) + " objects, the frame has " +
                std::to_string(records.size()));
  for (const auto& row : m_link_seconds)
    if (!row.empty() && row.size() != size_t(gpms))
      throw Error("OO runtime: an object's link costs name " + std::to_string(row.size()) + " GPMs, the machine has " +
                  std::to_string(gpms));
  for (size_t b = 0; b < m_batches_in.size(); ++b) {
    BatchRun r;
    for (uint32_t o : m_batches_in[b].objects) {
      Item geo;
      geo.object = o;
      geo.batch = int(b);
      geo.geometry = true;
      geo.vertices = vertices[o];
      r.items.push_back(geo);
      const std::vector<const TileWork*>& all = records[o];
      for (size_t k = 0; k < all.size(); k += size_t(spec.tiles_per_unit)) {
        Item chunk;
        chunk.object = o;
        chunk.batch = int(b);
        chunk.records.assign(all.begin() + std::ptrdiff_t(k),
                             all.begin() + std::ptrdiff_t(std::min(all.size(), k + size_t(spec.tiles_per_unit))));
        for (const TileWork* w : chunk.records) chunk.pixels += w->covered;
        r.pixels += chunk.pixels;
        r.items.push_back(std::move(chunk));
      }
    }
    r.items_left = int(r.items.size());
    m_items += r.items.size();
    m_batches.push_back(std::move(r));
  }
  m_geo_unit.assign(records.size(), -1);
  m_geo_gpm.assign(records.size(), -1);
  m_gpm.resize(size_t(m_n));
  if (m_spec.predictor && rates) start_engine(*rates);
  if (m_spec.predictor && !m_engine)
    for (size_t b = 0; b < m_batches.size() && b < size_t(spec.warmup_batches); ++b) m_batches[b].warmup = true;
}

void OORuntime::start_engine(const Rates& rates) {
  m_engine = std::make_unique<DistributionEngine>(m_n, rates);
  for (int g = 0; g < m_n; ++g) {
    const Gpm& s = m_gpm[size_t(g)];
    if (s.current >= 0) m_engine->assign(s.current, g, m_batches_in[size_t(s.current)].triangles);
    for (int b : s.pending) m_engine->assign(b, g, m_batches_in[size_t(b)].triangles);
  }
}

int OORuntime::queued() const {
  int q = 0;
  for (const Gpm& s : m_gpm) q += int(s.pending.size());
  return q;
}

// The GPM the next batch goes to.
int OORuntime::choose(int b) {
  if (!m_engine || m_batches[size_t(b)].warmup) {
    const int g = m_rr++ % m_n;
    if (m_exec.keeps_marks()) m_exec.decided(b, g, {}, "round-robin");
    return g;
  }
  for (int g = 0; g < m_n; ++g) {
    // Work reported for the batches it holds, the running item pro rata.
    double v = 0, p = 0;
    const Gpm& s = m_gpm[size_t(g)];
    if (s.current >= 0) {
      v = m_batches[size_t(s.current)].vertices_done;
      p = m_batches[size_t(s.current)].pixels_done;
      if (s.item && s.item->batch == s.current) {
        const double done = m_exec.progress(s.running);
        v += done * double(s.item->vertices);
        p += done * double(s.item->pixels);
      }
    }
    m_engine->set_elapsed(g, v, p);
  }
  std::vector<double> extra;  // screen affinity's link time per GPM (empty: none)
  if (m_spec.affinity > 0 && !m_link_seconds.empty()) {
    extra.assign(size_t(m_n), 0.0);
    for (uint32_t o : m_batches_in[size_t(b)].objects)
      if (!m_link_seconds[o].empty())
        for (int g = 0; g < m_n; ++g) extra[size_t(g)] += m_spec.affinity * m_link_seconds[o][size_t(g)];
  }
  const int g = m_engine->cheapest(extra);
  if (!extra.empty() && g != m_engine->earliest_free()) ++m_affine;
  if (m_exec.keeps_marks()) m_exec.decided(b, g, predicted(extra), "predicted free first");
  return g;
}

std::vector<double> OORuntime::predicted(const std::vector<double>& extra) const {
  std::vector<double> p(size_t(m_n), 0.0);
  for (int k = 0; k < m_n; ++k) p[size_t(k)] = m_engine->remaining(k) + (extra.empty() ? 0.0 : extra[size_t(k)]);
  return p;
}

void OORuntime::assign(int b, int g) {
  BatchRun& br = m_batches[size_t(b)];
  br.gpm = g;
  m_gpm[size_t(g)].pending.push_back(b);
  if (m_engine) m_engine->assign(b, g, m_batches_in[size_t(b)].triangles);
  if (m_spec.prealloc && !br.warmup) {
    const int u = m_exec.preallocate(g, m_batches_in[size_t(b)].objects, true, m_gpm[size_t(g)].last_copy);
    if (u >= 0) m_gpm[size_t(g)].last_copy = u;
    br.prealloc = u;
  }
}

// Assigns batches while the queue has room (always, without the hardware
// engine) and starts idle GPMs, until nothing changes. A GPM with nothing to
// do is free now, the earliest of all: it gets the next batch at once,
// whether the queue is full or not (the batch starts at once, so it does not
// wait in the queue). With round-robin, batches keep their order of GPMs.
void OORuntime::schedule() {
  for (bool changed = true; changed;) {
    changed = false;
    while (m_next < int(m_batches.size()) && (!m_spec.predictor || queued() < m_spec.batch_queue)) {
      const int b = m_next++;
      assign(b, choose(b));
      changed = true;
    }
    if (m_engine && m_next < int(m_batches.size()) && !m_batches[size_t(m_next)].warmup)
      for (int g = 0; g < m_n && m_next < int(m_batches.size()); ++g) {
        const Gpm& s = m_gpm[size_t(g)];
        if (s.running < 0 && s.todo.empty() && s.pending.empty()) {
          if (m_exec.keeps_marks()) m_exec.decided(m_next, g, predicted({}), "idle");
          assign(m_next++, g);
          changed = true;
        }
      }
    for (int g = 0; g < m_n; ++g) changed = advance(g) || changed;
  }
}

// Gives GPM g its next item if it is idle: from its batch, its next batch,
// or (split) another GPM's leftovers. Returns whether it started one.
bool OORuntime::advance(int g) {
  Gpm& s = m_gpm[size_t(g)];
  if (s.running >= 0) return false;
  if (s.todo.empty()) {
    s.current = -1;
    if (!s.pending.empty()) {
      const int b = s.pending.front();
      s.pending.pop_front();
      s.current = b;
      m_batches[size_t(b)].start = m_exec.now();
      m_exec.start_batch(g, m_batches_in[size_t(b)].objects);
      for (Item& it : m_batches[size_t(b)].items) s.todo.push_back(&it);
    } else if (!(m_spec.split && m_next == int(m_batches.size()) && steal(g))) {
      return false;
    }
  }
  Item* it = s.todo.front();
  s.todo.pop_front();
  issue(g, *it);
  return true;
}

bool OORuntime::steal(int g) {
  int victim = -1;
  size_t most = 1;
  const auto movable = [&](const Item* it) { return !it->geometry && m_geo_unit[it->object] >= 0; };
  for (int v = 0; v < m_n; ++v) {
    if (v == g) continue;
    const auto& todo = m_gpm[size_t(v)].todo;
    const size_t k = size_t(std::count_if(todo.begin(), todo.end(), movable));
    if (k > most) {
      most = k;
      victim = v;
    }
  }
  if (victim < 0) return false;
  auto& from = m_gpm[size_t(victim)].todo;
  // The later oo.split_share of them (half by default), at least one.
  size_t take = std::max<size_t>(1, size_t(double(most) * m_spec.split_share));
  std::vector<Item*> moved;
  for (auto it = from.end(); it != from.begin() && take > 0;) {
    --it;
    if (!movable(*it)) continue;
    moved.push_back(*it);
    it = from.erase(it);
    --take;
  }
  std::reverse(moved.begin(), moved.end());
  std::vector<uint32_t> objects;
  for (Item* it : moved) objects.push_back(it->object);
  Gpm& s = m_gpm[size_t(g)];
  const int copy = m_exec.preallocate(g, objects, false, s.last_copy);
  if (copy >= 0) s.last_copy = copy;
  for (Item* it : moved) {
    it->thief_copy = copy;
    s.todo.push_back(it);
  }
  s.current = moved.front()->batch;
  m_moved += int(moved.size());
  return true;
}

void OORuntime::issue(int g, Item& it) {
  Gpm& s = m_gpm[size_t(g)];
  const BatchRun& br = m_batches[size_t(it.batch)];
  int unit;
  if (it.geometry) {
    unit = m_exec.geometry(g, it.object, br.prealloc);
    m_geo_unit[it.object] = unit;
    m_geo_gpm[it.object] = g;
  } else {
    unit = m_exec.chunk(g, it.object, it.records, m_geo_unit[it.object], m_geo_gpm[it.object], br.prealloc, it.thief_copy);
  }
  s.running = unit;
  s.item = &it;
  ++m_issued;
  BatchRun& run = m_batches[size_t(it.batch)];
  if (g == run.gpm) {
    if (run.first_unit < 0) run.first_unit = unit;
    run.last_unit = unit;
  }
  if (size_t(unit) >= m_unit_gpm.size()) m_unit_gpm.resize(size_t(unit) + 1, -1);
  m_unit_gpm[size_t(unit)] = g;
}

void OORuntime::on_finish(int unit) {
  if (size_t(unit) >= m_unit_gpm.size() || m_unit_gpm[size_t(unit)] < 0) return;
  const int g = m_unit_gpm[size_t(unit)];
  Gpm& s = m_gpm[size_t(g)];
  if (s.running != unit) return;
  Item& it = *s.item;
  s.running = -1;
  s.item = nullptr;
  BatchRun& br = m_batches[size_t(it.batch)];
  br.vertices_done += double(it.vertices);
  br.pixels_done += double(it.pixels);
  if (--br.items_left == 0) batch_done(it.batch);
  schedule();
}

void OORuntime::batch_done(int b) {
  const BatchRun& br = m_batches[size_t(b)];
  if (br.first_unit >= 0 && m_exec.keeps_marks()) m_exec.batch_ran(b, br.gpm, br.first_unit, br.last_unit);
  if (m_engine) m_engine->finish(b);
  if (!br.warmup) return;
  const Batch& in = m_batches_in[size_t(b)];
  m_samples.push_back({double(in.triangles), double(in.vertices), double(br.pixels), m_exec.now() - br.start});
  const size_t warmups = size_t(std::count_if(m_batches.begin(), m_batches.end(), [](const BatchRun& x) { return x.warmup; }));
  if (m_samples.size() < warmups) return;
  // The first round is done: fit the rates and start predicting.
  try {
    m_fitted = Rates::fit(m_samples);
    start_engine(*m_fitted);
  } catch (const Error&) {
    // No work to fit from (an empty frame): stay round-robin.
  }
}

}  // namespace oovr
