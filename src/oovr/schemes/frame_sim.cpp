#include "oovr/schemes/frame_sim.h"

#include <algorithm>
#include <cmath>

#include "oovr/core/error.h"
#include "oovr/core/parallel.h"
#include "oovr/framework/oo_spec.h"

namespace oovr {

uint64_t SchemeResult::total_inter_gpm_bytes() const {
  uint64_t s = 0;
  for (uint64_t b : inter_gpm_bytes) s += b;
  return s;
}

double SchemeResult::best_to_worst() const {
  double lo = 0, hi = 0;
  bool first = true;
  for (double b : gpm_busy_s) {
    lo = first ? b : std::min(lo, b);
    hi = first ? b : std::max(hi, b);
    first = false;
  }
  return lo > 0 ? hi / lo : 0;
}

std::vector<ObjectRecords> records_by_object(const FrameTrace& t, size_t objects) {
  std::vector<ObjectRecords> r(objects);
  for (const TileWork& w : t.tiles) r[w.object].eye[w.eye].push_back(&w);
  return r;
}

FrameSim::FrameSim(const SchemeInput& in, int framebuffers) : m_in(in) {
  if (!in.scene || in.frames.empty()) throw Error("a scheme needs a scene and at least one frame");
  m_memory_spec = MemorySpec::from_config(in.config);
  m_timing_spec = TimingSpec::from_config(in.config);
  in.config.check_all_used();
  const FrameTrace& f = *in.frames[0];
  CarriedState* carried = in.carried.get();
  if (carried && carried->memory) {
    // The frame before left the memory system as it is: pages stay where
    // they were placed. The frame boundary invalidates what the
    // configuration says it does (remote caches).
    if (carried->framebuffers != framebuffers) throw Error("a carried memory system was laid out for another scheme");
    m_map = carried->map;
    m_layout = carried->layout;
    m_memory = carried->memory;
    m_colour = carried->colour;
    m_depth = carried->depth;
    m_memory->end_frame();
    m_before = m_memory->totals();
  } else {
    m_map = std::make_shared<AddressMap>(m_memory_spec.page, m_memory_spec.line);
    m_layout = std::make_shared<SceneLayout>(*m_map, *in.scene, f);
    m_colour.push_back(m_layout->colour_region());
    m_depth.push_back(m_layout->depth_region());
    for (int k = 1; k < framebuffers; ++k) {
      m_colour.push_back(m_map->add("frame" + std::to_string(k) + ".colour", Category::colour, m_layout->frame_bytes()));
      m_depth.push_back(m_map->add("frame" + std::to_string(k) + ".depth", Category::depth, m_layout->frame_bytes()));
    }
    m_memory = std::make_shared<MemorySystem>(m_memory_spec, *m_map);
    m_before = m_memory->totals();
    if (carried) {
      carried->map = m_map;
      carried->layout = m_layout;
      carried->memory = m_memory;
      carried->framebuffers = framebuffers;
      carried->colour = m_colour;
      carried->depth = m_depth;
    }
  }
  m_machine = std::make_unique<MachineModel>(m_timing_spec, m_memory_spec, m_memory->topology(), m_engine);
  m_last.assign(size_t(gpms()), -1);
  m_result.tile_inter_gpm_bytes.assign(size_t(f.tiles_x) * size_t(f.tiles_y), 0);
  m_result.config = in.config.resolved();
}

int FrameSim::add(int gpm, const WorkCounts& w, const UnitTraffic& t, std::vector<int> after, bool in_queue) {
  TimingEngine::Unit u;
  u.queue = in_queue ? m_machine->queue(gpm) : -1;
  u.demand = m_machine->demand(gpm, w, t);
  u.after = std::move(after);
  u.after.erase(std::remove(u.after.begin(), u.after.end(), -1), u.after.end());
  const int id = m_engine.add_unit(std::move(u));
  if (in_queue) m_last[size_t(gpm)] = id;
  m_unit_gpm.push_back(gpm);
  m_result.covered_fragments += w.covered;
  ++m_result.units;
  return id;
}

int FrameSim::geometry(int gpm, uint32_t object, int vertex_passes, uint64_t triangles, std::vector<int> after) {
  const Object& o = scene().objects[object];
  const Mesh& mesh = scene().meshes[size_t(o.mesh)];
  m_scratch.clear();
  const uint64_t line = m_memory_spec.line.value;
  const Region& vb = m_map->region(m_layout->vertex_region(o.mesh));
  const Region& ib = m_map->region(m_layout->index_region(o.mesh));
  for (uint64_t a = 0; a < mesh.vertices.size() * sizeof(Vertex); a += line) m_scratch.push_back({vb.base + a, Category::vertex, false});
  for (uint64_t a = 0; a < mesh.indices.size() * sizeof(uint32_t); a += line) m_scratch.push_back({ib.base + a, Category::index, false});
  UnitTraffic t;
  m_memory->access(gpm, int(object % uint32_t(sms())), m_scratch, t);
  WorkCounts w;
  w.vertices = uint64_t(vertex_passes) * mesh.vertices.size();
  w.triangles = triangles;
  return add(gpm, w, t, std::move(after));
}

void FrameSim::replay(int gpm, const TileWork& r, int fb, const FrameTrace& frame, UnitTraffic& total, WorkCounts& w) {
  m_scratch.clear();
  for (uint32_t k = 0; k < r.tex_count; ++k)
    m_scratch.push_back({m_layout->texture_line(frame.tex_lines[r.tex_begin + k]), Category::texture, false});
  for (int l = 0; l < m_layout->lines_per_tile(); ++l) {
    if (r.depth_read_mask & (1u << l))
      m_scratch.push_back({m_layout->frame_line(depth(fb), r.tile_x, r.tile_y, l), Category::depth, false});
    if (r.write_mask & (1u << l)) {
      m_scratch.push_back({m_layout->frame_line(depth(fb), r.tile_x, r.tile_y, l), Category::depth, true});
      m_scratch.push_back({m_layout->frame_line(colour(fb), r.tile_x, r.tile_y, l), Category::colour, true});
    }
  }
  UnitTraffic t;
  const uint32_t tile = uint32_t(r.tile_y) * uint32_t(frame.tiles_x) + r.tile_x;
  m_memory->access(gpm, int(tile % uint32_t(sms())), m_scratch, t);
  if (&frame == m_in.frames[0]) {
    m_result.tile_inter_gpm_bytes[tile] += t.total_inter_gpm_bytes();
    m_result.owner[{r.object, tile}] = gpm;
  }
  // Accumulate the record's traffic into the unit's.
  total.accesses += t.accesses;
  for (size_t g = 0; g < t.dram_read_bytes.size(); ++g) {
    total.dram_read_bytes[g] += t.dram_read_bytes[g];
    total.dram_write_bytes[g] += t.dram_write_bytes[g];
  }
  for (size_t l = 0; l < t.link_bytes.size(); ++l) total.link_bytes[l] += t.link_bytes[l];
  w.covered += r.covered;
  w.quads += r.quads;
  w.samples += r.samples;
  w.passed += r.passed;
}

int FrameSim::tiles(int gpm, std::span<const TileWork* const> records, int fb, const FrameTrace& frame,
                    std::vector<int> after, int from, uint64_t incoming) {
  TileJob job{gpm, {records.begin(), records.end()}, fb, std::move(after), from, incoming};
  return tiles_together({std::move(job)}, frame).front();
}

std::vector<int> FrameSim::tiles_together(const std::vector<TileJob>& jobs, const FrameTrace& frame) {
  const size_t n = jobs.size();
  std::vector<UnitTraffic> traffic(n);
  std::vector<WorkCounts> work(n);
  size_t rounds = 0;
  for (size_t j = 0; j < n; ++j) {
    traffic[j].reset(gpms(), int(m_memory->topology().links().size()));
    const TileJob& job = jobs[j];
    if (job.from >= 0 && job.from != job.gpm && job.incoming)
      m_memory->transfer(job.from, job.gpm, job.incoming, Category::vertex, traffic[j]);
    rounds = std::max(rounds, job.records.size());
  }
  for (size_t k = 0; k < rounds; ++k)
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (k + i) % n;
      if (k < jobs[j].records.size())
        replay(jobs[j].gpm, *jobs[j].records[k], jobs[j].fbs.empty() ? jobs[j].fb : jobs[j].fbs[k], frame, traffic[j], work[j]);
    }
  std::vector<int> units;
  for (size_t j = 0; j < n; ++j) units.push_back(add(jobs[j].gpm, work[j], traffic[j], jobs[j].after));
  return units;
}

int FrameSim::transfer(int from, int to, uint64_t bytes, Category c, std::vector<int> after) {
  UnitTraffic t;
  t.reset(gpms(), int(m_memory->topology().links().size()));
  m_memory->transfer(from, to, bytes, c, t);
  // A transfer between GPMs waits for the link latency of every hop.
  return add_movement(m_machine->transfer_demand(t), std::move(after),
                      m_memory_spec.link_latency.value * double(m_memory->topology().route(from, to).size()));
}

int FrameSim::add_movement(std::vector<std::pair<int, double>> demand, std::vector<int> after, double latency) {
  TimingEngine::Unit u;
  u.queue = -1;
  u.demand = std::move(demand);
  u.after = std::move(after);
  u.after.erase(std::remove(u.after.begin(), u.after.end(), -1), u.after.end());
  u.latency = latency;
  ++m_result.units;
  m_unit_gpm.push_back(-1);
  return m_engine.add_unit(std::move(u));
}

int FrameSim::preallocate(int gpm, std::span<const uint32_t> regions, std::vector<int> after) {
  UnitTraffic t;
  t.reset(gpms(), int(m_memory->topology().links().size()));
  uint64_t copied = 0;
  for (uint32_t r : regions) {
    const Region& reg = m_map->region(r);
    copied += m_memory->preallocate(reg.base, reg.bytes, gpm, t);
  }
  if (copied == 0) return -1;
  // The copies' DRAM reads and writes and their links.
  return add_movement(m_machine->demand(gpm, WorkCounts{}, t), std::move(after), m_memory_spec.link_latency.value);
}

int FrameSim::compose(int gpm, uint64_t pixels, std::vector<int> after) {
  WorkCounts w;
  w.composed = pixels;
  UnitTraffic t;
  t.reset(gpms(), int(m_memory->topology().links().size()));
  return add(gpm, w, t, std::move(after), false);
}

SchemeResult FrameSim::finish(const std::string& scheme, int frames_in_flight, const std::function<void(int)>& on_finish) {
  const TimingEngine::Result r = m_engine.run(on_finish);
  SchemeResult& s = m_result;
  s.scheme = scheme;
  s.gpms = gpms();
  s.frequency_hz = m_timing_spec.frequency.value;
  s.frames_in_flight = frames_in_flight;
  s.frame_latency_s = r.makespan;
  s.frame_latencies_s = {r.makespan};
  s.throughput_fps = r.makespan > 0 ? double(frames_in_flight) / r.makespan : 0;
  // A GPM is busy while any of its units runs: the union of their
  // intervals (its queue's units never overlap; composition may overlap them).
  std::vector<std::vector<std::pair<double, double>>> spans(static_cast<size_t>(gpms()));
  for (size_t i = 0; i < m_unit_gpm.size(); ++i)
    if (m_unit_gpm[i] >= 0) spans[size_t(m_unit_gpm[i])].push_back({r.units[i].start, r.units[i].finish});
  s.gpm_busy_s.assign(size_t(gpms()), 0);
  for (int g = 0; g < gpms(); ++g) {
    auto& v = spans[size_t(g)];
    std::sort(v.begin(), v.end());
    double end = -1, busy = 0;
    for (const auto& [a, b] : v) {
      if (a >= end) {
        busy += b - a;
        end = b;
      } else if (b > end) {
        busy += b - end;
        end = b;
      }
    }
    s.gpm_busy_s[size_t(g)] = busy;
  }
  // This frame's traffic: the totals since it began.
  const TrafficTotals& t = m_memory->totals();
  for (int c = 0; c < kCategories; ++c) s.inter_gpm_bytes[size_t(c)] = t.inter_gpm_bytes[size_t(c)] - m_before.inter_gpm_bytes[size_t(c)];
  s.local_dram_bytes = 0;
  for (int g = 0; g < gpms(); ++g)
    for (int c = 0; c < kCategories; ++c)
      s.local_dram_bytes += t.dram_read_bytes[size_t(g)][size_t(c)] - m_before.dram_read_bytes[size_t(g)][size_t(c)] +
                            t.dram_write_bytes[size_t(g)][size_t(c)] - m_before.dram_write_bytes[size_t(g)][size_t(c)];
  s.footprint_bytes = m_memory->footprint_bytes();
  return s;
}

void sort_first(FrameSim& sim, const std::function<int(int, int, int)>& owner, Geometry geometry) {
  const FrameTrace& f = sim.frame();
  const std::vector<ObjectRecords> objects = records_by_object(f, sim.scene().objects.size());
  const int n = sim.gpms();
  std::vector<std::vector<const TileWork*>> mine(static_cast<size_t>(n));
  for (uint32_t o = 0; o < objects.size(); ++o) {
    for (auto& m : mine) m.clear();
    std::vector<int> eyes_of(size_t(n), 0);  // bit e: the GPM owns tiles of eye e
    std::vector<uint64_t> triangles_of(size_t(n), 0);
    for (int e = 0; e < 2; ++e)
      for (const TileWork* r : objects[o].eye[e]) {
        const int g = owner(r->tile_x, r->tile_y, e);
        mine[size_t(g)].push_back(r);
        eyes_of[size_t(g)] |= 1 << e;
        triangles_of[size_t(g)] += r->triangles;
      }
    const ObjectWork& ow = f.objects[o];
    if (geometry == Geometry::shared) {
      // One GPM transforms the draw for both eyes; the owners receive the
      // set-up triangles of their tiles.
      const int geo_gpm = int(o % uint32_t(n));
      const int geo = sim.geometry(geo_gpm, o, 1, uint64_t(ow.setup[0]) + ow.setup[1]);
      std::vector<FrameSim::TileJob> jobs;
      for (int g = 0; g < n; ++g)
        if (!mine[size_t(g)].empty())
          jobs.push_back({g, mine[size_t(g)], 0, {geo}, geo_gpm, triangles_of[size_t(g)] * uint64_t(sim.timing().triangle_bytes)});
      sim.tiles_together(jobs, f);
      continue;
    }
    std::vector<FrameSim::TileJob> jobs;
    for (int g = 0; g < n; ++g) {
      if (mine[size_t(g)].empty()) continue;
      const int eyes = __builtin_popcount(unsigned(eyes_of[size_t(g)]));
      uint64_t tris = 0;
      for (int e = 0; e < 2; ++e)
        if (eyes_of[size_t(g)] & (1 << e)) tris += ow.setup[e];
      const int passes = geometry == Geometry::duplicated_smp ? 1 : eyes;
      jobs.push_back({g, mine[size_t(g)], 0, {sim.geometry(g, o, passes, tris)}});
    }
    sim.tiles_together(jobs, f);
  }
}

std::function<int(int, int, int)> eye_groups_interleaved(int n, const SceneLayout& layout) {
  const int group = std::max(1, n / 2);
  return [=, &layout](int tx, int ty, int eye) {
    const int first = n >= 2 ? eye * group : 0;
    const int size = n >= 2 ? (eye == 0 ? group : n - group) : 1;
    return first + layout.block_of(tx, ty) % size;
  };
}

int scheme_frames_needed(const std::string& name, const Config& config) {
  const SchemeFactory* f = Schemes::find(name);
  if (!f) return 1;
  Config c = config;
  const auto scheme = f->make();
  scheme->configure(c);
  return scheme->frames_needed(int(c.get_int("gpms", MemorySpec{}.gpms)));
}

SchemeResult run_scheme(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                        const Config& config, std::shared_ptr<CarriedState> carried) {
  const SchemeFactory* f = Schemes::find(name);
  if (!f) {
    std::string names;
    for (const auto& n : Schemes::names()) names += (names.empty() ? "" : ", ") + n;
    throw Error("unknown scheme '" + name + "' (schemes: " + names + ")");
  }
  const auto scheme = f->make();
  SchemeInput in;
  in.scene = &scene;
  in.frames = frames;
  in.config = config;
  in.carried = std::move(carried);
  scheme->configure(in.config);
  // OO-VR's keys are known to every scheme (a compare with --set oo.* runs
  // them all), and checked even where unused.
  OOSpec::check(in.config);
  return scheme->run(in);
}

SchemeResult run_scheme_window(const std::string& name, const Scene& scene, const std::vector<const FrameTrace*>& frames,
                               const Config& config, int window, std::vector<SchemeResult>* runs) {
  const int m = scheme_frames_needed(name, config);
  if (window < 1 || window % m != 0)
    throw Error(name + " renders " + std::to_string(m) + " frames at once (one per GPM): the number of frames (" +
                std::to_string(window) + ") must be a multiple of " + std::to_string(m));
  if (int(frames.size()) < window)
    throw Error("not enough frames of trace: " + std::to_string(window) + " needed, " + std::to_string(frames.size()) + " given");
  // In sequence on one memory system, after an unmeasured warm-up pass over
  // the same frames: data is then where a game running these views would
  // have it (pre-allocated copies included), and the distribution engine's
  // rates are fitted.
  const auto group = [&](size_t i) {
    const auto first = frames.begin() + std::ptrdiff_t(i) * m;
    return std::vector<const FrameTrace*>(first, first + m);
  };
  const auto carried = std::make_shared<CarriedState>();
  for (size_t i = 0; i < size_t(window / m); ++i) (void)run_scheme(name, scene, group(i), config, carried);
  std::vector<SchemeResult> all;
  for (size_t i = 0; i < size_t(window / m); ++i) all.push_back(run_scheme(name, scene, group(i), config, carried));
  SchemeResult s = all.front();
  s.frame_latencies_s.clear();
  double time = 0;  // seconds the window's frames take, frames in flight overlapping
  for (auto& x : s.inter_gpm_bytes) x = 0;
  s.local_dram_bytes = s.covered_fragments = s.units = 0;
  std::vector<double> busy(s.gpm_busy_s.size(), 0);
  for (const SchemeResult& r : all) {
    s.frame_latencies_s.insert(s.frame_latencies_s.end(), r.frame_latencies_s.begin(), r.frame_latencies_s.end());
    time += double(r.frames_in_flight) / r.throughput_fps;
    for (size_t c = 0; c < s.inter_gpm_bytes.size(); ++c) s.inter_gpm_bytes[c] += r.inter_gpm_bytes[c];
    s.local_dram_bytes += r.local_dram_bytes;
    s.covered_fragments += r.covered_fragments;
    s.units += r.units;
    s.footprint_bytes = std::max(s.footprint_bytes, r.footprint_bytes);
    for (size_t g = 0; g < busy.size(); ++g) busy[g] += r.gpm_busy_s[g] / double(all.size());
  }
  // Per frame: bytes summed over the window's frames, divided by them.
  const auto per_frame = [&](uint64_t v) { return (v + uint64_t(window) / 2) / uint64_t(window); };
  for (auto& x : s.inter_gpm_bytes) x = per_frame(x);
  s.local_dram_bytes = per_frame(s.local_dram_bytes);
  s.gpm_busy_s = busy;
  double sum = 0;
  for (double l : s.frame_latencies_s) sum += l;
  s.frame_latency_s = sum / double(s.frame_latencies_s.size());
  s.throughput_fps = double(window) / time;
  if (runs) *runs = std::move(all);
  return s;
}

}  // namespace oovr
