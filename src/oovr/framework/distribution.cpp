#include "oovr/framework/distribution.h"

#include <algorithm>
#include <cmath>

#include "oovr/core/error.h"

namespace oovr {

Rates Rates::fit(std::span<const BatchSample> samples) {
  double tt = 0, ty = 0, vv = 0, pp = 0, vp = 0, vy = 0, py = 0;
  for (const auto& s : samples) {
    tt += s.triangles * s.triangles;
    ty += s.triangles * s.seconds;
    vv += s.vertices * s.vertices;
    pp += s.pixels * s.pixels;
    vp += s.vertices * s.pixels;
    vy += s.vertices * s.seconds;
    py += s.pixels * s.seconds;
  }
  if (!(tt > 0) || !(vv + pp > 0)) throw Error("distribution engine: no batch with work to fit its rates from");
  Rates r;
  r.c0 = ty / tt;
  // Sum of squared residuals of (c1, c2), for choosing among fits.
  const auto residual = [&](double per_vertex, double per_pixel) {
    double e = 0;
    for (const auto& s : samples) {
      const double d = s.seconds - per_vertex * s.vertices - per_pixel * s.pixels;
      e += d * d;
    }
    return e;
  };
  const double det = vv * pp - vp * vp;
  bool joint = false;
  if (std::abs(det) > 1e-12 * vv * pp) {
    const double c1 = (vy * pp - py * vp) / det, c2 = (py * vv - vy * vp) / det;
    if (c1 >= 0 && c2 >= 0) {
      r.c1 = c1;
      r.c2 = c2;
      joint = true;
    }
  }
  if (!joint) {
    const double only_v = vv > 0 ? std::max(0.0, vy / vv) : 0, only_p = pp > 0 ? std::max(0.0, py / pp) : 0;
    if (residual(only_v, 0) <= residual(0, only_p)) r.c1 = only_v;
    else r.c2 = only_p;
  }
  return r;
}

DistributionEngine::DistributionEngine(int gpms, const Rates& rates) : m_rates(rates), m_elapsed(size_t(gpms), 0) {
  if (gpms < 1) throw Error("distribution engine: needs at least one GPM");
}

void DistributionEngine::assign(int id, int gpm, uint64_t triangles) {
  m_held.push_back({id, gpm, m_rates.c0 * double(triangles)});
}

void DistributionEngine::finish(int id) {
  m_held.erase(std::remove_if(m_held.begin(), m_held.end(), [&](const Held& h) { return h.id == id; }), m_held.end());
}

void DistributionEngine::set_elapsed(int gpm, double vertices, double pixels) {
  m_elapsed[size_t(gpm)] = m_rates.c1 * vertices + m_rates.c2 * pixels;
}

double DistributionEngine::remaining(int gpm) const {
  double total = 0;
  bool holds = false;
  for (const Held& h : m_held)
    if (h.gpm == gpm) {
      total += h.predicted;
      holds = true;
    }
  return holds ? std::max(0.0, total - m_elapsed[size_t(gpm)]) : 0.0;
}

int DistributionEngine::earliest_free() const { return cheapest({}); }

int DistributionEngine::cheapest(std::span<const double> extra) const {
  if (!extra.empty() && extra.size() != m_elapsed.size())
    throw Error("distribution engine: " + std::to_string(extra.size()) + " extra costs for " + std::to_string(m_elapsed.size()) +
                " GPMs");
  // Ties (two GPMs predicted free now) go to the one holding fewer batches,
  // then to the lower id.
  const auto held = [&](int g) { return std::count_if(m_held.begin(), m_held.end(), [&](const Held& h) { return h.gpm == g; }); };
  const auto cost = [&](int g) { return remaining(g) + (extra.empty() ? 0.0 : extra[size_t(g)]); };
  int best = 0;
  for (int g = 1; g < int(m_elapsed.size()); ++g) {
    const double r = cost(g), b = cost(best);
    if (r < b || (r == b && held(g) < held(best))) best = g;
  }
  return best;
}

EngineStorage engine_storage(int gpms, int batch_queue) { return {gpms * 2 * 64, batch_queue * 16, gpms * 3 * 32}; }

}  // namespace oovr
