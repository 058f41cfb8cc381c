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
// The mechanisms are the framework's (framework/: the application, the
// middleware's batches, the runtime with its distribution engine, batch
// queue, pre-allocation and split); this file only runs them on the
// simulated machine: it is the runtime's executor. The predictor's fit is
// kept for the frames that follow (it is the GPMs' rates), so a measured
// frame after the warm-up uses the predictor from its first batch.
//
// Derived from the trace: per object, its set-up triangles of both eyes and
// its tile records (both eyes). A GPM receives an object's draw once (one
// multi-view draw) before its first work on it, including a moved chunk's
// GPM; geometry is not split, and a moved chunk receives its set-up
// triangles from the GPM that did the geometry. Pixels reach the final
// frame through sort-last composition (schemes/composition.h) to their
// owner: with DHC the owner of their strip (direct send), else the root
// (gather), unless sort_last.composition names another. Every covered
// fragment is rendered once; nothing is duplicated but the data the split
// copies.
//
// oo-vr-affinity is OO-VR with screen affinity (oo.affinity = 1; oovr's own
// idea, not the paper's; framework/runtime.h). What oovr measures of OO-VR
// is that, its texture reads made local, its links carry the pixels a GPM
// renders outside its own strip: their colour to the strip's owner and
// their depth tests in the owner's depth buffer (docs/paper-comparison.md,
// P11). So the engine weighs each GPM's predicted free time with the link
// time those pixels would take if the batch ran there. Where a batch's
// pixels fall is known once its geometry is done, too late to choose; the
// engine uses where its objects' pixels fell in the previous frame (a table
// keyed by the draw: mesh, material, pass, view and placement), which a VR
// frame rate keeps close. A draw not in the table costs nothing anywhere.
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "oovr/core/hash.h"
#include "oovr/core/units.h"
#include "oovr/framework/oo_application.h"
#include "oovr/framework/runtime.h"
#include "oovr/schemes/composition.h"

namespace oovr {
namespace {

constexpr const char* kRatesKey = "oo.rates";
constexpr const char* kFootprintKey = "oo.footprint";

// A draw as screen affinity knows it from one frame to the next: a checksum
// of its mesh, material, pass, view and placement, as two exact halves (the
// carried values are doubles).
using Signature = std::pair<double, double>;
Signature signature(const Object& o) {
  std::string b;
  const auto put = [&](const void* p, size_t n) { b.append(static_cast<const char*>(p), n); };
  put(&o.mesh, sizeof o.mesh);
  put(&o.material, sizeof o.material);
  put(&o.pass, sizeof o.pass);
  const auto view = uint8_t(o.view);
  put(&view, 1);
  put(&o.world_from_object.m, sizeof o.world_from_object.m);
  const uint64_t h = checksum64(b);
  return {double(h >> 32), double(h & 0xffffffffu)};
}

// Screen affinity's table: per draw signature, the link bytes its pixels
// cost on each GPM, carried from frame to frame as rows of 2 + gpms values.
std::map<Signature, std::vector<double>> read_footprints(const CarriedState* carried, int gpms) {
  std::map<Signature, std::vector<double>> table;
  if (!carried) return table;
  const auto it = carried->values.find(kFootprintKey);
  if (it == carried->values.end()) return table;
  const std::vector<double>& v = it->second;
  const size_t row = 2 + size_t(gpms);
  if (v.size() % row != 0) return table;  // not this machine's rows (a window runs on one): none
  for (size_t k = 0; k < v.size(); k += row)
    table.emplace(Signature{v[k], v[k + 1]},
                  std::vector<double>(v.begin() + std::ptrdiff_t(k + 2), v.begin() + std::ptrdiff_t(k + row)));
  return table;
}

// The runtime's decisions as units on the simulated machine.
class Machine final : public RuntimeExecutor {
 public:
  Machine(FrameSim& sim, Composer& composer)
      : m_sim(sim),
        m_composer(composer),
        m_f(sim.frame()),
        m_last_object(size_t(sim.gpms()), -1),
        m_command(size_t(sim.gpms()), std::vector<int>(sim.draws(sim.frame()).size(), -1)) {}

  double now() const override { return m_sim.engine().now(); }
  double progress(int unit) const override { return 1.0 - m_sim.engine().work_left(unit); }

  int preallocate(int gpm, const std::vector<uint32_t>& objects, bool geometry, int after) override {
    std::vector<uint32_t> regions;
    const auto add = [&](uint32_t x) {
      if (std::find(regions.begin(), regions.end(), x) == regions.end()) regions.push_back(x);
    };
    for (uint32_t o : objects) {
      const Object& so = m_sim.draws(m_f)[o];
      if (geometry) {
        add(m_sim.layout().vertex_region(so.mesh));
        add(m_sim.layout().index_region(so.mesh));
      }
      for (int t : m_sim.scene().textures_of(so)) add(m_sim.layout().texture_region(t));
    }
    return m_sim.preallocate(gpm, regions, {after});
  }

  // The timeline's marks (kept only when a timeline is asked for).
  bool keeps_marks() const override { return m_sim.keeps_timeline(); }
  void decided(int batch, int gpm, std::span<const double> predicted, const char* why) override {
    std::vector<std::pair<std::string, double>> args = {{"batch", batch}, {"gpm", gpm}};
    for (size_t g = 0; g < predicted.size(); ++g)
      args.push_back({"predicted_free_us_gpm" + std::to_string(g), predicted[g] * 1e6});
    m_sim.mark_instant("batch " + std::to_string(batch) + " to GPM " + std::to_string(gpm) + " (" + why + ")", "decision", gpm,
                       std::move(args));
  }
  void batch_ran(int batch, int gpm, int first, int last) override {
    m_sim.mark_span("batch " + std::to_string(batch), "batch", gpm, first, last, {{"batch", batch}});
  }

  void start_batch(int gpm, const std::vector<uint32_t>& objects) override {
    for (uint32_t o : objects) receive(gpm, o);
  }

  int geometry(int gpm, uint32_t object, int prealloc) override {
    begin(gpm, object);
    // Both views at once: one vertex pass, set-up for both eyes (SMP).
    const ObjectWork& ow = m_f.objects[object];
    return m_sim.geometry(gpm, object, 1, uint64_t(ow.setup[0]) + ow.setup[1], {prealloc});
  }

  int chunk(int gpm, uint32_t object, std::span<const TileWork* const> records, int geo_unit, int geo_gpm, int prealloc,
            int thief_copy) override {
    begin(gpm, object);
    FrameSim::TileJob job{gpm, {records.begin(), records.end()}, 0, {geo_unit, prealloc, thief_copy}};
    if (geo_gpm != gpm) {
      uint64_t tris = 0;
      for (const TileWork* w : records) tris += w->triangles;
      job.from = geo_gpm;
      job.incoming = tris * uint64_t(m_sim.timing().triangle_bytes);
    }
    m_composer.target(job);
    const int unit = m_sim.tiles_together({job}, m_f).front();
    m_composer.send(job, unit);
    return unit;
  }

 private:
  // GPM `gpm`'s front end receives `object`'s draw (once).
  int receive(int gpm, uint32_t object) {
    int& cmd = m_command[size_t(gpm)][object];
    if (cmd < 0) cmd = m_sim.command(gpm);
    return cmd;
  }

  // GPM `gpm` works on `object`: the draw it worked on before has ended
  // there, and this one's (received now if it was not) is current.
  void begin(int gpm, uint32_t object) {
    int& last = m_last_object[size_t(gpm)];
    if (last == int(object)) return;
    if (last >= 0) m_sim.end_draw(gpm);
    last = int(object);
    m_sim.use_draw(gpm, receive(gpm, object));
  }

  FrameSim& m_sim;
  Composer& m_composer;
  const FrameTrace& m_f;
  std::vector<int> m_last_object;
  std::vector<std::vector<int>> m_command;  // per GPM and object: the unit that received its draw
};

class OO final : public Scheme {
 public:
  OO(std::string name, OOSpec mechanisms) : m_name(std::move(name)), m_mechanisms(mechanisms) {}

  // The switches as this scheme reads them, given or its own defaults
  // (oo-app all off, oo-vr all on), recorded with its results.
  void configure(MachineSpec& m) const override { m.own<OOSettings>("oo").record(m_mechanisms, m.entries); }

  SchemeResult run(const SchemeInput& in) const override {
    const OOSpec spec = in.spec->own<OOSettings>("oo").resolve(m_mechanisms);
    const int n = in.spec->memory.gpms;
    FrameSim sim(in, sort_last_framebuffers(n));
    // Copies dropped and refused during this frame (the memory system's
    // totals run on from frame to frame).
    const FrameSim::Copies before = sim.copies();
    const FrameTrace& f = sim.frame();
    // DHC is direct send to vertical strips; sort_last.composition, when
    // configured, overrides the switch.
    Composer composer(sim, sim.spec().composition,
                      spec.distributed_composition ? CompositionAlgorithm::direct_send : CompositionAlgorithm::gather);
    Machine machine(sim, composer);

    const size_t draws = sim.draws(f).size();
    const OOApplication app = make_application(sim.scene(), f.frame_width, f.frame_height, f.frame);
    std::vector<std::vector<const TileWork*>> records(draws);
    std::vector<uint64_t> vertices(draws);
    const std::vector<ObjectRecords> by_object = records_by_object(f, draws);
    for (size_t o = 0; o < records.size(); ++o) {
      records[o] = by_object[o].both();
      vertices[o] = app.objects()[o].vertices;
    }
    // The predictor's rates, when an earlier frame fitted them.
    std::optional<Rates> rates;
    CarriedState* carried = in.carried.get();
    if (carried) {
      const auto it = carried->values.find(kRatesKey);
      if (it != carried->values.end() && it->second.size() == 3) rates = Rates{it->second[0], it->second[1], it->second[2]};
    }
    // Screen affinity: where each object's pixels fell in the previous
    // frame, priced at one link's bandwidth; this frame's for the next.
    std::vector<std::vector<double>> link_seconds;
    if (spec.affinity > 0) {
      const std::map<Signature, std::vector<double>> last = read_footprints(carried, n);
      const double per_byte = 1.0 / sim.spec().memory.link_bandwidth.value;
      std::vector<double> next;
      link_seconds.resize(draws);
      for (size_t o = 0; o < draws; ++o) {
        const Signature key = signature(sim.draws(f)[o]);
        if (const auto it = last.find(key); it != last.end())
          for (double bytes : it->second) link_seconds[o].push_back(bytes * per_byte);
        next.push_back(key.first);
        next.push_back(key.second);
        for (int g = 0; g < n; ++g) {
          uint64_t bytes = 0;
          for (const TileWork* r : records[o]) bytes += composer.remote_bytes(*r, g);
          next.push_back(double(bytes));
        }
      }
      if (carried) carried->values[kFootprintKey] = std::move(next);
    }
    OORuntime runtime(spec, n, make_batches(app, {spec.tsl_threshold, uint64_t(spec.batch_triangles)}), records, vertices,
                      machine, rates, std::move(link_seconds));
    runtime.start();
    // A deferred composition starts once the runtime has given out every
    // piece of work: each GPM's rounds then follow its last one.
    bool closed = false;
    const auto close = [&] {
      if (!closed && runtime.all_issued()) {
        composer.close();
        closed = true;
      }
    };
    close();
    SchemeResult r = sim.finish(m_name, 1, [&](int unit) {
      runtime.on_finish(unit);
      close();
    });
    const FrameSim::Copies after = sim.copies();
    copies(r, after.peak_bytes, after.evicted - before.evicted, after.refused - before.refused);
    if (carried && runtime.fitted()) {
      const Rates& x = *runtime.fitted();
      carried->values[kRatesKey] = {x.c0, x.c1, x.c2};
    }
    notes(r, spec, composer.algorithm(), n, sim, runtime);
    return r;
  }

 private:
  // Pre-allocated and split copies (Section 5.2): the most one GPM has held
  // (with no cap, where the scene's copies fit); this frame's copies dropped
  // for room and pages refused for want of it are the memory system's
  // statistics, and a note when there are any.
  static void copies(SchemeResult& r, uint64_t peak, uint64_t evicted, uint64_t refused) {
    r.add_own("copies.peak_bytes", double(peak), "B");
    if (evicted || refused)
      r.notes.push_back("copies: " + std::to_string(evicted) + " pages dropped for room, " + std::to_string(refused) +
                        " not copied for want of it (" + format_bytes(Bytes{peak}) + " held at most on one GPM)");
  }

  static void notes(SchemeResult& r, const OOSpec& spec, CompositionAlgorithm composition, int n, const FrameSim& sim,
                    const OORuntime& runtime) {
    uint64_t tris = 0;
    const auto& batches = runtime.batches();
    for (const auto& b : batches) tris += b.triangles;
    r.add_own("batches", double(batches.size()), "");
    const size_t objects = sim.draws(sim.frame()).size();
    r.add_own("objects", double(objects), "");
    r.add_own("batch_triangles", batches.empty() ? 0.0 : double(tris) / double(batches.size()), "");
    r.notes.push_back(std::to_string(batches.size()) + " batches of " + std::to_string(objects) + " objects (mean " +
                      std::to_string(batches.empty() ? 0 : tris / batches.size()) + " triangles); " +
                      (spec.predictor ? "predictor" : "round-robin") + ", pre-allocation " + (spec.prealloc ? "on" : "off") +
                      ", split " + (spec.split ? "on" : "off") + ", composition " + composition_algorithm_name(composition));
    if (const DistributionEngine* engine = runtime.engine()) {
      const Rates& x = engine->rates();
      char buf[160];
      std::snprintf(buf, sizeof buf, "predictor rates: c0 %.3g ns/triangle, c1 %.3g ns/vertex, c2 %.3g ns/pixel", x.c0 * 1e9,
                    x.c1 * 1e9, x.c2 * 1e9);
      r.notes.push_back(buf);
      // The linear predictor's fitted costs (Section 5.2, Equation 3): per
      // triangle, per transformed vertex and per pixel.
      r.add_own("predictor.c0", x.c0, "s");
      r.add_own("predictor.c1", x.c1, "s");
      r.add_own("predictor.c2", x.c2, "s");
      const EngineStorage st = engine_storage(n, spec.batch_queue);
      r.add_own("engine_storage", double(st.total()), "bit");
      r.notes.push_back("distribution engine storage: " + std::to_string(st.total()) + " bits (counters " +
                        std::to_string(st.counter_bits) + ", batch ids " + std::to_string(st.batch_id_bits) + ", registers " +
                        std::to_string(st.register_bits) + "; the paper: 960)");
    }
    r.add_own("moved_chunks", double(runtime.moved_chunks()), "");
    if (spec.affinity > 0) {
      r.add_own("affine_batches", double(runtime.affine_batches()), "");
      r.notes.push_back("screen affinity (weight " + format_number(spec.affinity) + "): " +
                        std::to_string(runtime.affine_batches()) + " batches sent elsewhere than the GPM predicted free first");
    }
    if (runtime.moved_chunks())
      r.notes.push_back(std::to_string(runtime.moved_chunks()) + " chunks of fragment work moved to idle GPMs");
  }

  std::string m_name;
  OOSpec m_mechanisms;
};

OOSpec mechanisms(bool on) {
  OOSpec s;
  s.predictor = s.prealloc = s.split = s.distributed_composition = on;
  return s;
}

const Schemes::Add reg_app("oo-app", {"OO_APP: multi-view objects batched by texture sharing, round-robin, root composition",
                                      [] { return std::make_unique<OO>("oo-app", mechanisms(false)); },
                                      80,
                                      {"oo", "sort_last"}});
const Schemes::Add reg_vr("oo-vr", {"OO-VR: OO_APP + distribution engine (predictor, pre-allocation, split) + DHC",
                                    [] { return std::make_unique<OO>("oo-vr", mechanisms(true)); },
                                    90,
                                    {"oo", "sort_last"}});
OOSpec with_affinity(OOSpec s) {
  s.affinity = 1;
  return s;
}
const Schemes::Add reg_affinity(
    "oo-vr-affinity", {"OO-VR with screen affinity (oovr's): batches weigh the link time of pixels outside their GPM's strip",
                       [] { return std::make_unique<OO>("oo-vr-affinity", with_affinity(mechanisms(true))); },
                       95,
                       {"oo", "sort_last"}});

}  // namespace
}  // namespace oovr
