// oo-app and oo-vr (paper Sections 5 and 6): the OO-VR framework on the
// simulated machine, one implementation with each mechanism a switch
// (framework/oo_spec.h), registered twice with the paper's two settings:
//
//   oo-app  OO_APP: the programming model and middleware alone. Every object
//           is one multi-view task (both views on one GPM, geometry once with
//           SMP, the same texture data); objects are batched by texture
//           sharing (Equation 1); batches are dealt round-robin by software;
//           data is placed by first touch; all colour goes to the root, GPM 0.
//   oo-vr   OO_APP plus the object-aware runtime distribution engine
//           (Section 5.2: batches go to the GPM predicted free first,
//           pre-allocation units copy each batch's data ahead of use, the
//           leftovers of large batches are split over idle GPMs with their
//           data duplicated) and distributed hardware composition (Section
//           5.3: N vertical strips, each composed by its owner's ROPs).
//
// How the engine runs: it holds at most oo.batch_queue batches assigned but
// not started. Whenever a slot is free it gives the next batch to the GPM
// whose counters predict it free first (total: c0 * triangles of the batches
// it holds; elapsed: c1 * vertices transformed + c2 * pixels rendered so
// far, read from the GPMs' progress), and that GPM's pre-allocation unit
// starts copying the batch's vertex, index and texture pages, in batch
// order. A GPM starts its next batch when it ends one (after the batch's
// copy). The first oo.warmup_batches batches of a run go round-robin with
// first-touch data, and their measured times fit c0, c1, c2 (least squares);
// the fit is kept for the frames that follow (it is the GPMs' rates), so a
// measured frame after the warm-up uses the predictor from its first batch.
//
// Derived from the trace: per object, its set-up triangles of both eyes and
// its tile records (both eyes); a batch's work is, per object, one geometry
// unit, then its records in chunks of oo.tiles_per_unit tiles, which is what
// the fine-grained split hands to idle GPMs (geometry is not split; a moved
// chunk receives its set-up triangles from the GPM that did the geometry).
// A GPM writes pixels of the final frame it owns (its strip with DHC; all of
// them on the root) straight into the frame, and the others into its own
// colour and depth buffer; after each chunk, those lines go to their owner
// (category composition), whose ROPs merge them by depth beside its own
// rendering. Every covered fragment is rendered once; nothing is duplicated
// but the data the split copies.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <deque>

#include "oovr/core/error.h"
#include "oovr/framework/distribution.h"
#include "oovr/framework/middleware.h"
#include "oovr/framework/oo_application.h"
#include "oovr/framework/oo_spec.h"
#include "oovr/schemes/frame_sim.h"

namespace oovr {
namespace {

constexpr const char* kRatesKey = "oo.rates";

struct Item {
  uint32_t object = 0;
  int batch = 0;
  bool geometry = false;
  std::vector<const TileWork*> records;
  uint64_t vertices = 0, pixels = 0;  // what the GPM reports to the engine
  int thief_copy = -1;                // for a moved chunk: its new GPM's data copy
};

struct BatchRun {
  std::vector<Item> items;
  int gpm = -1;
  int items_left = 0;
  int prealloc = -1;
  double start = -1;
  bool warmup = false;
  double vertices_done = 0, pixels_done = 0;
  uint64_t pixels = 0;
};

class Run {
 public:
  Run(const SchemeInput& in, const OOSpec& spec, const std::string& name)
      : m_spec(spec), m_name(name), m_n(int(in.config.get_int("gpms", MemorySpec{}.gpms))), m_sim(in, m_n + 1),
        m_f(m_sim.frame()), m_carried(in.carried.get()) {
    const OOApplication app = make_application(m_sim.scene(), m_f.frame_width, m_f.frame_height);
    m_batches_in = make_batches(app, {spec.tsl_threshold, uint64_t(spec.batch_triangles)});
    const std::vector<ObjectRecords> records = records_by_object(m_f, m_sim.scene().objects.size());
    for (size_t b = 0; b < m_batches_in.size(); ++b) {
      BatchRun r;
      for (uint32_t o : m_batches_in[b].objects) {
        Item geo;
        geo.object = o;
        geo.batch = int(b);
        geo.geometry = true;
        geo.vertices = app.objects()[o].vertices;
        r.items.push_back(geo);
        std::vector<const TileWork*> all = records[o].eye[0];
        all.insert(all.end(), records[o].eye[1].begin(), records[o].eye[1].end());
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
      m_batches.push_back(std::move(r));
    }
    m_geo_unit.assign(m_sim.scene().objects.size(), -1);
    m_geo_gpm.assign(m_sim.scene().objects.size(), -1);
    m_gpm.resize(size_t(m_n));
    // The predictor's rates, when an earlier frame fitted them.
    if (m_spec.predictor && m_carried) {
      const auto it = m_carried->values.find(kRatesKey);
      if (it != m_carried->values.end() && it->second.size() == 3) start_engine({it->second[0], it->second[1], it->second[2]});
    }
    if (m_spec.predictor && !m_engine)
      for (size_t b = 0; b < m_batches.size() && b < size_t(spec.warmup_batches); ++b) m_batches[b].warmup = true;
  }

  SchemeResult go() {
    schedule();
    SchemeResult r = m_sim.finish(m_name, 1, [&](int unit) { on_finish(unit); });
    uint64_t tris = 0;
    for (const auto& b : m_batches_in) tris += b.triangles;
    r.notes.push_back(std::to_string(m_batches_in.size()) + " batches of " + std::to_string(m_sim.scene().objects.size()) +
                      " objects (mean " + std::to_string(m_batches_in.empty() ? 0 : tris / m_batches_in.size()) +
                      " triangles); " + (m_spec.predictor ? "predictor" : "round-robin") + ", pre-allocation " +
                      (m_spec.prealloc ? "on" : "off") + ", split " + (m_spec.split ? "on" : "off") + ", " +
                      (m_spec.distributed_composition ? "distributed" : "root") + " composition");
    if (m_engine) {
      const Rates& x = m_engine->rates();
      char buf[160];
      std::snprintf(buf, sizeof buf, "predictor rates: c0 %.3g ns/triangle, c1 %.3g ns/vertex, c2 %.3g ns/pixel", x.c0 * 1e9,
                    x.c1 * 1e9, x.c2 * 1e9);
      r.notes.push_back(buf);
      const EngineStorage st = engine_storage(m_n, m_spec.batch_queue);
      r.notes.push_back("distribution engine storage: " + std::to_string(st.total()) + " bits (counters " +
                        std::to_string(st.counter_bits) + ", batch ids " + std::to_string(st.batch_id_bits) + ", registers " +
                        std::to_string(st.register_bits) + "; the paper: 960)");
    }
    if (m_moved) r.notes.push_back(std::to_string(m_moved) + " chunks of fragment work moved to idle GPMs");
    return r;
  }

 private:
  struct Gpm {
    std::deque<int> pending;  // batches assigned, not started
    int current = -1;         // the batch it works on
    std::deque<Item*> todo;   // its items of that batch not started
    int running = -1;         // unit of the item it runs
    Item* item = nullptr;
    int last_copy = -1;       // its pre-allocation unit's last copy (copies run in batch order)
  };

  void start_engine(const Rates& rates) {
    m_engine = std::make_unique<DistributionEngine>(m_n, rates);
    for (int g = 0; g < m_n; ++g) {
      const Gpm& s = m_gpm[size_t(g)];
      if (s.current >= 0) m_engine->assign(s.current, g, m_batches_in[size_t(s.current)].triangles);
      for (int b : s.pending) m_engine->assign(b, g, m_batches_in[size_t(b)].triangles);
    }
  }

  int queued() const {
    int q = 0;
    for (const Gpm& s : m_gpm) q += int(s.pending.size());
    return q;
  }

  // The GPM the next batch goes to.
  int choose(int b) {
    if (!m_engine || m_batches[size_t(b)].warmup) return m_rr++ % m_n;
    for (int g = 0; g < m_n; ++g) {
      // Work reported for the batches it holds, the running item pro rata.
      double v = 0, p = 0;
      const Gpm& s = m_gpm[size_t(g)];
      if (s.current >= 0) {
        v = m_batches[size_t(s.current)].vertices_done;
        p = m_batches[size_t(s.current)].pixels_done;
        if (s.item && s.item->batch == s.current) {
          const double done = 1.0 - m_sim.engine().work_left(s.running);
          v += done * double(s.item->vertices);
          p += done * double(s.item->pixels);
        }
      }
      m_engine->set_elapsed(g, v, p);
    }
    return m_engine->earliest_free();
  }

  std::vector<uint32_t> regions_of(const std::vector<uint32_t>& objects, bool geometry) const {
    std::vector<uint32_t> r;
    const auto add = [&](uint32_t x) {
      if (std::find(r.begin(), r.end(), x) == r.end()) r.push_back(x);
    };
    for (uint32_t o : objects) {
      const Object& so = m_sim.scene().objects[o];
      if (geometry) {
        add(m_sim.layout().vertex_region(so.mesh));
        add(m_sim.layout().index_region(so.mesh));
      }
      const Material& m = m_sim.scene().materials[size_t(so.material)];
      for (int t : {m.diffuse, m.lightmap})
        if (t >= 0) add(m_sim.layout().texture_region(t));
    }
    return r;
  }

  void assign(int b, int g) {
    BatchRun& br = m_batches[size_t(b)];
    br.gpm = g;
    m_gpm[size_t(g)].pending.push_back(b);
    if (m_engine) m_engine->assign(b, g, m_batches_in[size_t(b)].triangles);
    if (m_spec.prealloc && !br.warmup) {
      const int u = m_sim.preallocate(g, regions_of(m_batches_in[size_t(b)].objects, true), {m_gpm[size_t(g)].last_copy});
      if (u >= 0) m_gpm[size_t(g)].last_copy = u;
      br.prealloc = u;
    }
  }

  // Assigns batches while the queue has room and starts idle GPMs, until
  // nothing changes. A GPM with nothing to do is free now, the earliest of
  // all: it gets the next batch at once, whether the queue is full or not
  // (the batch starts at once, so it does not wait in the queue). With
  // round-robin, batches keep their order of GPMs.
  void schedule() {
    for (bool changed = true; changed;) {
      changed = false;
      while (m_next < int(m_batches.size()) && queued() < m_spec.batch_queue) {
        const int b = m_next++;
        assign(b, choose(b));
        changed = true;
      }
      if (m_engine && m_next < int(m_batches.size()) && !m_batches[size_t(m_next)].warmup)
        for (int g = 0; g < m_n && m_next < int(m_batches.size()); ++g) {
          const Gpm& s = m_gpm[size_t(g)];
          if (s.running < 0 && s.todo.empty() && s.pending.empty()) {
            assign(m_next++, g);
            changed = true;
          }
        }
      for (int g = 0; g < m_n; ++g) changed = advance(g) || changed;
    }
  }

  // Gives GPM g its next item if it is idle: from its batch, its next batch,
  // or (split) another GPM's leftovers. Returns whether it started one.
  bool advance(int g) {
    Gpm& s = m_gpm[size_t(g)];
    if (s.running >= 0) return false;
    if (s.todo.empty()) {
      s.current = -1;
      if (!s.pending.empty()) {
        const int b = s.pending.front();
        s.pending.pop_front();
        s.current = b;
        m_batches[size_t(b)].start = m_sim.engine().now();
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

  // Fine-grained split: an idle GPM takes the later half of the chunks not
  // yet started (whose geometry has been issued) of the GPM with the most,
  // and its pre-allocation unit copies the textures they sample.
  bool steal(int g) {
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
    size_t take = most / 2;
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
    const int copy = m_sim.preallocate(g, regions_of(objects, false), {s.last_copy});
    if (copy >= 0) s.last_copy = copy;
    for (Item* it : moved) {
      it->thief_copy = copy;
      s.todo.push_back(it);
    }
    s.current = moved.front()->batch;
    m_moved += int(moved.size());
    return true;
  }

  void issue(int g, Item& it) {
    Gpm& s = m_gpm[size_t(g)];
    const BatchRun& br = m_batches[size_t(it.batch)];
    const ObjectWork& ow = m_f.objects[it.object];
    int unit;
    if (it.geometry) {
      // Both views at once: one vertex pass, set-up for both eyes (SMP).
      unit = m_sim.geometry(g, it.object, 1, uint64_t(ow.setup[0]) + ow.setup[1], {br.prealloc});
      m_geo_unit[it.object] = unit;
      m_geo_gpm[it.object] = g;
    } else {
      FrameSim::TileJob job{g, it.records, 0, {m_geo_unit[it.object], br.prealloc, it.thief_copy}};
      if (m_geo_gpm[it.object] != g) {
        uint64_t tris = 0;
        for (const TileWork* w : it.records) tris += w->triangles;
        job.from = m_geo_gpm[it.object];
        job.incoming = tris * uint64_t(m_sim.timing().triangle_bytes);
      }
      // Per record: the final frame where g owns the pixels, else g's own buffer.
      std::vector<uint64_t> lines_to(size_t(m_n), 0);
      for (const TileWork* w : it.records) {
        const int owner = m_spec.distributed_composition ? vertical_strip_owner(w->tile_x, m_f.tiles_x, m_n) : 0;
        job.fbs.push_back(owner == g ? 0 : 1 + g);
        if (owner != g) lines_to[size_t(owner)] += uint64_t(std::popcount(w->write_mask));
      }
      unit = m_sim.tiles_together({job}, m_f).front();
      // The colour and depth of lines owned elsewhere go to their owner,
      // whose ROPs merge them (Section 5.3; on the root without DHC).
      for (int o = 0; o < m_n; ++o)
        if (lines_to[size_t(o)]) {
          const int sent = m_sim.transfer(g, o, lines_to[size_t(o)] * m_f.line_bytes * 2, Category::composition, {unit});
          m_sim.compose(o, lines_to[size_t(o)] * (m_f.line_bytes / 4), {sent});
        }
    }
    s.running = unit;
    s.item = &it;
    if (size_t(unit) >= m_unit_gpm.size()) m_unit_gpm.resize(size_t(unit) + 1, -1);
    m_unit_gpm[size_t(unit)] = g;
  }

  void on_finish(int unit) {
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

  void batch_done(int b) {
    const BatchRun& br = m_batches[size_t(b)];
    if (m_engine) m_engine->finish(b);
    if (!br.warmup) return;
    const Batch& in = m_batches_in[size_t(b)];
    m_samples.push_back({double(in.triangles), double(in.vertices), double(br.pixels), m_sim.engine().now() - br.start});
    const size_t warmups = size_t(std::count_if(m_batches.begin(), m_batches.end(), [](const BatchRun& x) { return x.warmup; }));
    if (m_samples.size() < warmups) return;
    // The first round is done: fit the rates and start predicting.
    try {
      const Rates r = Rates::fit(m_samples);
      start_engine(r);
      if (m_carried) m_carried->values[kRatesKey] = {r.c0, r.c1, r.c2};
    } catch (const Error&) {
      // No work to fit from (an empty frame): stay round-robin.
    }
  }

  OOSpec m_spec;
  std::string m_name;
  int m_n;
  FrameSim m_sim;
  const FrameTrace& m_f;
  CarriedState* m_carried;
  std::vector<Batch> m_batches_in;
  std::vector<BatchRun> m_batches;
  std::vector<int> m_geo_unit, m_geo_gpm;
  std::vector<Gpm> m_gpm;
  std::vector<int> m_unit_gpm;
  std::unique_ptr<DistributionEngine> m_engine;
  std::vector<BatchSample> m_samples;
  int m_next = 0;
  int m_rr = 0;
  int m_moved = 0;
};

class OO final : public Scheme {
 public:
  OO(std::string name, OOSpec mechanisms) : m_name(std::move(name)), m_mechanisms(mechanisms) {}
  SchemeResult run(const SchemeInput& in) const override {
    const OOSpec spec = OOSpec::from_config(in.config, m_mechanisms);
    Run r(in, spec, m_name);
    return r.go();
  }

 private:
  std::string m_name;
  OOSpec m_mechanisms;
};

OOSpec mechanisms(bool on) {
  OOSpec s;
  s.predictor = s.prealloc = s.split = s.distributed_composition = on;
  return s;
}

const Schemes::Add reg_app("oo-app", {"OO_APP: multi-view objects batched by texture sharing, round-robin, root composition",
                                      [] { return std::make_unique<OO>("oo-app", mechanisms(false)); }});
const Schemes::Add reg_vr("oo-vr", {"OO-VR: OO_APP + distribution engine (predictor, pre-allocation, split) + DHC",
                                    [] { return std::make_unique<OO>("oo-vr", mechanisms(true)); }});

}  // namespace
}  // namespace oovr
