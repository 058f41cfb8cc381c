#include "oovr/schemes/frame_sim.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>

#include "oovr/core/error.h"
#include "oovr/core/parallel.h"
#include "oovr/core/sort.h"
#include "oovr/core/units.h"

namespace oovr {

const char* timeline_kind_name(TimelineUnit::Kind k) {
  switch (k) {
    case TimelineUnit::Kind::command: return "draw";
    case TimelineUnit::Kind::geometry: return "geometry";
    case TimelineUnit::Kind::tiles: return "tiles";
    case TimelineUnit::Kind::compose: return "compose";
    case TimelineUnit::Kind::transfer: return "transfer";
    case TimelineUnit::Kind::prealloc: return "copy";
  }
  return "unit";
}

uint64_t SchemeResult::total_inter_gpm_bytes() const {
  uint64_t s = 0;
  for (uint64_t b : inter_gpm_bytes) s += b;
  return s;
}

int SchemeResult::owner_of(uint32_t object, uint32_t tile) const {
  const std::pair<uint32_t, uint32_t> key{object, tile};
  const auto it = std::lower_bound(owner.begin(), owner.end(), key, [](const auto& e, const auto& k) { return e.first < k; });
  return it != owner.end() && it->first == key ? it->second : -1;
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

namespace {

std::atomic<bool> g_law_checks{true};
std::atomic<bool> g_repeats_counted{true};

// What each memory call folds into the calls' hash first (FrameSim::mix).
enum CallTag : uint64_t {
  kEndFrame = 1,
  kEndDraw,
  kPlace,
  kGeometry,
  kRecord,
  kJob,
  kTransfer,
  kPreallocate,
  kFinish,
  kCopies,
  kTiles
};

}  // namespace

void FrameSim::set_law_checks(bool on) { g_law_checks = on; }
bool FrameSim::law_checks() { return g_law_checks; }
void FrameSim::set_repeats_counted(bool on) { g_repeats_counted = on; }

namespace {

// How a message names an argument: "transfer(from_gpm=7): ".
std::string named(const char* fn, const char* param, int64_t value) {
  return std::string(fn) + "(" + param + "=" + std::to_string(value) + "): ";
}

}  // namespace

void FrameSim::no_gpm(int gpm, const char* fn, const char* param) const {
  throw Error(named(fn, param, gpm) + "GPM " + std::to_string(gpm) + " does not exist (GPMs 0 to " + std::to_string(gpms() - 1) +
              ")");
}

void FrameSim::no_fb(int fb, const char* fn, const char* param) const {
  throw Error(named(fn, param, fb) + "framebuffer " + std::to_string(fb) + " does not exist (this FrameSim has " +
              std::to_string(m_colour.size()) + ")");
}

int FrameSim::unit_arg(int unit, const char* fn, const char* param) const {
  const int64_t n = int64_t(m_engine.units());
  if (unit < 0 || unit >= n)
    throw Error(named(fn, param, unit) + "unit " + std::to_string(unit) + " has not been added (units 0 to " +
                std::to_string(n - 1) + ")");
  return unit;
}

const std::vector<int>& FrameSim::after_arg(const std::vector<int>& after, const char* fn) const {
  const int64_t n = int64_t(m_engine.units());
  for (int u : after)
    if (u < -1 || u >= n)
      throw Error(std::string(fn) + "(after): unit " + std::to_string(u) + " has not been added (units 0 to " +
                  std::to_string(n - 1) + "; -1 for none)");
  return after;
}

const FrameTrace& FrameSim::frame_arg(const FrameTrace& frame, const char* fn) const {
  if (std::find(m_in.frames.begin(), m_in.frames.end(), &frame) == m_in.frames.end())
    throw Error(std::string(fn) + ": the records are not of this run's frames");
  return frame;
}

void FrameSim::check(const MachineSpec& spec) {
  // Pinned placement homes only the regions a program pins through
  // MemorySystem::pin (the memory tests do); no scheme names homes, so it
  // would fail at the first page touched.
  if (spec.memory.placement == "pinned")
    throw Error(
        "configuration key 'memory.placement': 'pinned' homes only regions a program pins to GPMs (MemorySystem::pin) "
        "and no scheme does; use first-touch, interleaved, preallocated or replicated");
}

FrameSim::FrameSim(const SchemeInput& in, int framebuffers) : m_in(in) {
  if (!in.scene || in.frames.empty() || !in.spec) throw Error("a scheme needs a scene, a machine and at least one frame");
  check(*in.spec);
  m_memory_spec = in.spec->memory;
  m_timing_spec = in.spec->timing;
  const FrameTrace& f = *in.frames[0];
  CarriedState* carried = in.carried.get();
  if (carried) {
    m_recording = carried->recording.get();
    m_playing = carried->playing.get();
    m_calls = carried->calls;
  }
  if (carried && carried->layout) {
    // The frame before left the memory system as it is: pages stay where
    // they were placed. The frame boundary invalidates what the
    // configuration says it does (remote caches).
    if (carried->framebuffers != framebuffers) throw Error("a carried memory system was laid out for another scheme");
    m_map = carried->map;
    m_layout = carried->layout;
    m_memory = carried->memory;
    m_topology = carried->topology;
    m_colour = carried->colour;
    m_depth = carried->depth;
    mix({kEndFrame});
    if (m_memory) {
      m_memory->end_frame();
      m_before = m_memory->totals();
      m_memory->report(m_stats_before);
    }
  } else {
    m_map = std::make_shared<AddressMap>(m_memory_spec.page, m_memory_spec.line);
    m_layout = std::make_shared<SceneLayout>(*m_map, *in.scene, f);
    m_colour.push_back(m_layout->colour_region());
    m_depth.push_back(m_layout->depth_region());
    for (int k = 1; k < framebuffers; ++k) {
      m_colour.push_back(m_map->add("frame" + std::to_string(k) + ".colour", Category::colour, m_layout->frame_bytes()));
      m_depth.push_back(m_map->add("frame" + std::to_string(k) + ".depth", Category::depth, m_layout->frame_bytes()));
    }
    if (m_playing) {
      // The played run's links, for its timing; no caches.
      m_topology = Topologies::find(m_memory_spec.topology)->make(gpms());
    } else {
      m_memory = std::make_shared<MemorySystem>(m_memory_spec, *m_map);
      m_topology = std::shared_ptr<const Topology>(m_memory, &m_memory->topology());
      m_before = m_memory->totals();
      m_memory->report(m_stats_before);
    }
    if (carried) {
      carried->map = m_map;
      carried->layout = m_layout;
      carried->memory = m_memory;
      carried->topology = m_topology;
      carried->framebuffers = framebuffers;
      carried->colour = m_colour;
      carried->depth = m_depth;
    }
  }
  // A record's repeats in an L1 set are counted, not replayed (replay),
  // where a texture's lines fall in the L1's sets by their index: the
  // texture's base, a page, a multiple of the sets' span. The LRU rule too
  // where the L1 replaces the least recently used way (its reads are
  // Cache::access's; the policy is lru.cpp, which reads only the order of
  // last uses), where its scratch is bounded (FrameTrace::repeats_derivable).
  if (m_memory && g_repeats_counted) {
    const uint64_t sets = m_memory->l1_set_mask() + 1;
    const int ways = m_memory_spec.l1.ways;
    if (FrameTrace::repeats_derivable(sets, 0) && m_memory_spec.page.value % (sets * m_memory_spec.line.value) == 0) {
      m_repeat_sets = sets;
      const bool lru = m_memory_spec.l1.replacement == "lru" && FrameTrace::repeats_derivable(sets, ways);
      m_repeat_lru_ways = lru ? ways : 0;
    }
  }
  // The frames themselves, so that a tape is played back only on the
  // frames it was recorded on: their numbers, sizes and every record (a
  // checksum; the texture lines' contents are left out, as long as the
  // trace: frames with the same records and other lines are not made).
  if (taped())
    for (const FrameTrace* t : in.frames)
      mix({uint64_t(t->frame), uint64_t(t->tiles.size()), uint64_t(t->tex_lines.size()), t->records_checksum()});
  m_machine = std::make_unique<MachineModel>(m_timing_spec, m_memory_spec, topology(), m_engine);
  m_last.assign(size_t(gpms()), -1);
  m_draw.assign(size_t(gpms()), -1);
  m_draw_ends.assign(size_t(gpms()), {});
  m_draws_received.assign(size_t(gpms()), 0);
  m_result.tile_inter_gpm_bytes.assign(size_t(f.tiles_x) * size_t(f.tiles_y), 0);
  m_result.config = in.spec->entries;
  if (law_checks()) m_ledger = std::make_unique<RunLedger>(in.frames);
}

MemorySystem& FrameSim::memory() {
  if (!m_memory) throw TapeMismatch("the scheme reads the memory system, which a played run does not have");
  return *m_memory;
}

FrameSim::Copies FrameSim::copies() {
  mix({kCopies});
  Copies c;
  c.evicted = answer_value([&] { return m_memory->totals().copies_evicted; });
  c.refused = answer_value([&] { return m_memory->totals().copies_refused; });
  c.peak_bytes = answer_value([&] {
    uint64_t peak = 0;
    for (int g = 0; g < gpms(); ++g) peak = std::max(peak, m_memory->copy_peak_bytes(g));
    return peak;
  });
  return c;
}

void FrameSim::place(uint64_t address, int gpm) {
  gpm_arg(gpm, "place");
  mix({kPlace, address, uint64_t(gpm)});
  if (m_memory) (void)m_memory->place(address, gpm);
}

int FrameSim::last_unit(int gpm) const { return m_last[size_t(gpm_arg(gpm, "last_unit"))]; }

void FrameSim::declare_repeats(int times) {
  if (times < 1 || times > 1000) throw Error(named("declare_repeats", "times", times) + "times must be 1 to 1000");
  if (m_ledger) m_ledger->allow_repeats(times);
}

UnitTraffic FrameSim::empty_traffic() const {
  UnitTraffic t;
  t.reset(gpms(), int(topology().links().size()));
  return t;
}

int FrameSim::add(int gpm, const WorkCounts& w, const UnitTraffic& t, std::vector<int> after, TimelineUnit info, bool in_queue) {
  TimingEngine::Unit u;
  u.queue = in_queue ? m_machine->queue(gpm) : -1;
  u.demand = m_machine->demand(gpm, w, t);
  u.after = std::move(after);
  if (in_queue) u.after.push_back(m_draw[size_t(gpm)]);  // the draw has reached the pipeline
  u.after.erase(std::remove(u.after.begin(), u.after.end(), -1), u.after.end());
  const int id = m_engine.add_unit(std::move(u));
  if (in_queue) m_last[size_t(gpm)] = id;
  m_unit_gpm.push_back(gpm);
  info.gpm = gpm;
  if (keeps_timeline()) m_unit_info.push_back(info);
  m_result.covered_fragments += w.covered;
  m_result.vertices += w.vertices;
  ++m_result.units;
  return id;
}

int FrameSim::command(int gpm, int draws) {
  gpm_arg(gpm, "command");
  if (draws < 1) throw Error(named("command", "draws", draws) + "draws must be at least 1");
  TimingEngine::Unit u;
  u.queue = m_machine->front_queue(gpm);
  u.latency = m_machine->draw_seconds(draws);
  // The front end's FIFO: this draw waits for the end of the one
  // gpm.draws_ahead before it.
  const size_t i = m_draws_received[size_t(gpm)]++;
  const size_t ahead = size_t(m_timing_spec.draws_ahead);
  const auto& ends = m_draw_ends[size_t(gpm)];
  if (i >= ahead && i - ahead < ends.size() && ends[i - ahead] >= 0) u.after.push_back(ends[i - ahead]);
  const int id = m_engine.add_unit(std::move(u));
  m_draw[size_t(gpm)] = id;
  if (m_ledger) m_ledger->received(id);
  m_unit_gpm.push_back(gpm);
  if (keeps_timeline()) m_unit_info.push_back({TimelineUnit::Kind::command, 0, gpm});
  m_result.draws += uint64_t(draws);
  ++m_result.units;
  return id;
}

void FrameSim::use_draw(int gpm, int command_unit) {
  m_draw[size_t(gpm_arg(gpm, "use_draw"))] = unit_arg(command_unit, "use_draw", "command_unit");
}

void FrameSim::end_draw(int gpm) {
  if (gpm == -1) {
    for (int g = 0; g < gpms(); ++g) end_draw(g);
    return;
  }
  gpm_arg(gpm, "end_draw");
  // The draw is over when the last unit of the pipeline (or its command,
  // when it had no work here) is.
  const int last = m_last[size_t(gpm)];
  m_draw_ends[size_t(gpm)].push_back(std::max(last, m_draw[size_t(gpm)]));
  mix({kEndDraw, uint64_t(gpm)});
  if (m_memory) m_memory->end_draw(gpm);
}

int FrameSim::geometry(int gpm, uint32_t object, int vertex_passes, uint64_t triangles, std::vector<int> after, int frame_k) {
  if (frame_k < 0 || size_t(frame_k) >= m_in.frames.size())
    throw Error(named("geometry", "frame_k", frame_k) + "frame " + std::to_string(frame_k) + " does not exist (frames 0 to " +
                std::to_string(m_in.frames.size() - 1) + ")");
  gpm_arg(gpm, "geometry");
  const Object& o = object_arg(object, frame(frame_k), "geometry");
  if (vertex_passes < 1 || vertex_passes > 2)
    throw Error(named("geometry", "vertex_passes", vertex_passes) + "vertex_passes is 1 (SMP) or 2 (one per eye)");
  after_arg(after, "geometry");
  const uint64_t vertices = uint64_t(vertex_passes) * scene().meshes[size_t(o.mesh)].vertices.size();
  return geometry_unit(gpm, object, o, 0, 1, vertices, triangles, std::move(after));
}

int FrameSim::geometry_part(int gpm, uint32_t object, double begin, double end, double vertex_cost, uint64_t triangles,
                            std::vector<int> after) {
  gpm_arg(gpm, "geometry_part");
  const Object& o = object_arg(object, frame(), "geometry_part");
  if (!(begin >= 0 && begin <= end && end <= 1))
    throw Error("geometry_part(begin=" + format_number(begin) + ", end=" + format_number(end) +
                "): a share of the object's vertices is 0 <= begin <= end <= 1");
  if (!(vertex_cost >= 0 && vertex_cost <= 1))
    throw Error("geometry_part(vertex_cost=" + format_number(vertex_cost) +
                "): the share of the vertex shader run is from 0 to 1");
  after_arg(after, "geometry_part");
  const double vertices = (end - begin) * vertex_cost * double(scene().meshes[size_t(o.mesh)].vertices.size());
  return geometry_unit(gpm, object, o, begin, end, uint64_t(std::llround(vertices)), triangles, std::move(after));
}

const Object& FrameSim::object_arg(uint32_t object, const FrameTrace& f, const char* fn) const {
  const std::vector<Object>& objects = draws(f);
  if (object >= objects.size())
    throw Error(named(fn, "object", int64_t(object)) + "object " + std::to_string(object) + " does not exist (objects 0 to " +
                std::to_string(int64_t(objects.size()) - 1) + ")");
  return objects[object];
}

int FrameSim::geometry_unit(int gpm, uint32_t object, const Object& o, double begin, double end, uint64_t vertices,
                            uint64_t triangles, std::vector<int> after) {
  if (m_ledger) m_ledger->work(gpm, m_draw[size_t(gpm)], object, "geometry");
  UnitTraffic t = empty_traffic();
  mix({kGeometry, uint64_t(gpm), uint64_t(object), uint64_t(o.mesh), std::bit_cast<uint64_t>(begin),
       std::bit_cast<uint64_t>(end)});
  answer_traffic(t, [&] {
    const Mesh& mesh = scene().meshes[size_t(o.mesh)];
    m_scratch.clear();
    const uint64_t line = m_memory_spec.line.value;
    // The lines holding bytes [begin, end) of a buffer of `bytes`.
    const auto lines = [&](uint64_t base, uint64_t bytes, Category c) {
      const uint64_t from = uint64_t(std::floor(begin * double(bytes))), to = uint64_t(std::ceil(end * double(bytes)));
      for (uint64_t a = from / line * line; a < to; a += line) m_scratch.push_back({base + a, c, false});
    };
    lines(m_map->region(m_layout->vertex_region(o.mesh)).base, mesh.vertex_bytes(), Category::vertex);
    lines(m_map->region(m_layout->index_region(o.mesh)).base, mesh.indices.size() * sizeof(uint32_t), Category::index);
    m_memory->access(gpm, int(object % uint32_t(sms())), m_scratch, t);
  });
  WorkCounts w;
  w.vertices = vertices;
  w.triangles = triangles;
  TimelineUnit info;
  info.kind = TimelineUnit::Kind::geometry;
  info.object = int(object);
  return add(gpm, w, t, std::move(after), info);
}

const std::shared_ptr<const TexLinesWithoutRepeats>& FrameSim::without_repeats(const FrameTrace& frame) {
  if (&frame != m_repeats_of) {
    m_repeats = frame.tex_lines_without_repeats(m_repeat_sets, m_repeat_lru_ways);
    m_repeats_of = &frame;
  }
  return m_repeats;
}

void FrameSim::replay(int gpm, const TileWork& r, int colour_fb, int depth_fb, const FrameTrace& frame, UnitTraffic& total,
                      WorkCounts& w) {
  if (m_ledger) m_ledger->rasterised(frame, r, gpm, m_draw[size_t(gpm)], colour_fb);
  const uint32_t tile = uint32_t(r.tile_y) * uint32_t(frame.tiles_x) + r.tile_x;
  if (&frame == m_in.frames[0]) m_owner_log.push_back({{r.object, tile}, gpm});
  // The record names its lines (its frame is mixed in by tiles_checked): which
  // one, on which GPM and framebuffers.
  mix({kRecord, uint64_t(gpm), uint64_t(&r - frame.tiles.data()), uint64_t(colour_fb), uint64_t(depth_fb)});
  if (!m_playing) {
    // The texture lines written in place (no push_back's check per line),
    // less the record's repeats in its L1: a texture read of the line its
    // L1 set last read within the record is of the set's most recently used
    // line, a hit that changes nothing (Cache::access), and with LRU a sure
    // hit whose line the record reads again before the set may miss leaves
    // the set's order as it was; each is counted, not replayed. Most of a
    // frame's reads are such (82 to 95%: FrameTrace::tex_lines_without_repeats),
    // and the list without them, derived once per frame, is shared by every
    // scheme, pass and sweep point that replays the frame.
    const TexLine* in = frame.tex_lines.data() + r.tex_begin;
    uint64_t count = r.tex_count, repeats = 0;
    if (m_repeat_sets) {
      const size_t rec = size_t(&r - frame.tiles.data());
      const std::shared_ptr<const TexLinesWithoutRepeats>& kept = without_repeats(frame);
      if (kept && rec < frame.tiles.size() && &frame.tiles[rec] == &r) {
        in = kept->lines.data() + kept->begin[rec];
        count = kept->begin[rec + 1] - kept->begin[rec];
        repeats = r.tex_count - count;
      }
    }
    // The texture reads go to the memory system as listed (it finds their
    // addresses), the framebuffer's lines after them, named by the record's
    // masks (line by line: depth read, colour read as blending reads the
    // frame's colour, depth write, colour write): each framebuffer's tile
    // found once (its block and slot take four integer divisions), its
    // lines one every line's bytes from there. Bits past a tile's lines name
    // none.
    const int per_tile = m_layout->lines_per_tile();
    const uint32_t on_tile = per_tile >= 32 ? ~0u : (1u << per_tile) - 1;
    TileLines fb{0,
                 0,
                 r.depth_read_mask & on_tile,
                 r.colour_read_mask & on_tile,
                 r.depth_write_mask & on_tile,
                 r.colour_write_mask & on_tile};
    if (fb.depth_read | fb.colour_read | fb.depth_write | fb.colour_write) {
      fb.depth = m_layout->tile_address(depth(depth_fb), r.tile_x, r.tile_y);
      fb.colour = m_layout->tile_address(colour(colour_fb), r.tile_x, r.tile_y);
    }
    // Straight into the unit's total (access adds to it); the record's
    // own inter-GPM bytes are what the total gained.
    const uint64_t before = total.total_inter_gpm_bytes();
    m_memory->access(gpm, int(tile % uint32_t(sms())), *m_layout, {in, size_t(count)}, fb, total, repeats);
    if (&frame == m_in.frames[0]) m_result.tile_inter_gpm_bytes[tile] += total.total_inter_gpm_bytes() - before;
  }
  w.covered += r.covered;
  w.quads += r.quads;
  w.fragment_instructions += uint64_t(r.quads) * 4 * frame.objects[r.object].fragment_instructions;
  w.samples += r.samples;
  w.passed += r.passed;
}

int FrameSim::tiles(int gpm, std::span<const TileWork* const> records, int fb, const FrameTrace& frame, std::vector<int> after,
                    int from, uint64_t incoming) {
  frame_arg(frame, "tiles");
  gpm_arg(gpm, "tiles");
  fb_arg(fb, "tiles");
  after_arg(after, "tiles");
  if (from != -1) gpm_arg(from, "tiles", "from_gpm");
  TileJob job{gpm, {records.begin(), records.end()}, fb, std::move(after), from, incoming};
  return tiles_checked({std::move(job)}, frame).front();
}

std::vector<int> FrameSim::tiles_together(const std::vector<TileJob>& jobs, const FrameTrace& frame) {
  if (jobs.empty()) return {};
  frame_arg(frame, "tiles_together");
  for (const TileJob& j : jobs) {
    gpm_arg(j.gpm, "tiles_together", "gpm");
    fb_arg(j.fb, "tiles_together", "fb");
    after_arg(j.after, "tiles_together");
    if (j.from != -1) gpm_arg(j.from, "tiles_together", "from_gpm");
    for (const std::vector<int>* per : {&j.fbs, &j.depth_fbs}) {
      if (!per->empty() && per->size() != j.records.size())
        throw Error("tiles_together: per-record framebuffers must be one per record (" + std::to_string(j.records.size()) +
                    "), not " + std::to_string(per->size()));
      for (int f : *per) fb_arg(f, "tiles_together", "fbs");
    }
  }
  return tiles_checked(jobs, frame);
}

std::vector<int> FrameSim::tiles_checked(const std::vector<TileJob>& jobs, const FrameTrace& frame) {
  const size_t n = jobs.size();
  // The jobs' traffic in storage kept from the last call (taken, so that a
  // call made while this one runs would only allocate its own).
  std::vector<UnitTraffic> traffic = std::move(m_job_traffic);
  traffic.resize(n);
  for (UnitTraffic& t : traffic) t.reset(gpms(), int(topology().links().size()));
  std::vector<WorkCounts> work(n);
  std::vector<std::vector<int>> after(n);
  size_t rounds = 0;
  for (size_t j = 0; j < n; ++j) {
    const TileJob& job = jobs[j];
    // Room for the set-up's transfer and the draw (add()) as well: copied
    // at its size, the list was allocated again for each.
    after[j].reserve(job.after.size() + 2);
    after[j].assign(job.after.begin(), job.after.end());
    // The set-up triangles come over the links first (with their latency).
    if (job.from >= 0 && job.from != job.gpm && job.incoming)
      after[j].push_back(transfer(job.from, job.gpm, job.incoming, Category::vertex, job.after));
    rounds = std::max(rounds, job.records.size());
  }
  // Which of the run's frames the records are of.
  mix({kTiles, uint64_t(std::find(m_in.frames.begin(), m_in.frames.end(), &frame) - m_in.frames.begin())});
  for (size_t k = 0; k < rounds; ++k)
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (k + i) % n;
      const TileJob& job = jobs[j];
      if (k >= job.records.size()) continue;
      const int colour_fb = job.fbs.empty() ? job.fb : job.fbs[k];
      const int depth_fb = job.depth_fbs.empty() ? colour_fb : job.depth_fbs[k];
      replay(job.gpm, *job.records[k], colour_fb, depth_fb, frame, traffic[j], work[j]);
    }
  // Each job's traffic, the sum over its records (added up by replay when
  // not playing), is one answer.
  for (size_t j = 0; j < n; ++j) {
    mix({kJob});
    answer_traffic(traffic[j], [] {});
  }
  std::vector<int> units;
  for (size_t j = 0; j < n; ++j) {
    TimelineUnit info;
    info.kind = TimelineUnit::Kind::tiles;
    info.object = jobs[j].records.empty() ? -1 : int(jobs[j].records.front()->object);
    units.push_back(add(jobs[j].gpm, work[j], traffic[j], std::move(after[j]), info));
  }
  m_job_traffic = std::move(traffic);
  return units;
}

int FrameSim::transfer(int from, int to, uint64_t bytes, Category c, std::vector<int> after) {
  gpm_arg(from, "transfer", "from_gpm");
  gpm_arg(to, "transfer", "to_gpm");
  after_arg(after, "transfer");
  UnitTraffic t = empty_traffic();
  mix({kTransfer, uint64_t(from), uint64_t(to), bytes, uint64_t(c)});
  answer_traffic(t, [&] { m_memory->transfer(from, to, bytes, c, t); });
  // A transfer between GPMs waits for the link latency of every hop.
  TimelineUnit info;
  info.kind = TimelineUnit::Kind::transfer;
  info.gpm = to;
  info.from = from;
  return add_movement(m_machine->transfer_demand(t), std::move(after),
                      m_memory_spec.link_latency.value * double(topology().route(from, to).size()), info);
}

int FrameSim::add_movement(std::vector<std::pair<int, double>> demand, std::vector<int> after, double latency,
                           TimelineUnit info) {
  TimingEngine::Unit u;
  u.queue = -1;
  u.demand = std::move(demand);
  u.after = std::move(after);
  u.after.erase(std::remove(u.after.begin(), u.after.end(), -1), u.after.end());
  u.latency = latency;
  ++m_result.units;
  m_unit_gpm.push_back(-1);
  if (keeps_timeline()) m_unit_info.push_back(info);
  return m_engine.add_unit(std::move(u));
}

int FrameSim::preallocate(int gpm, std::span<const uint32_t> regions, std::vector<int> after) {
  gpm_arg(gpm, "preallocate");
  after_arg(after, "preallocate");
  UnitTraffic t = empty_traffic();
  mix({kPreallocate, uint64_t(gpm)});
  for (uint32_t r : regions) mix({r});
  // The bytes copied, then the copies' traffic (which the first fills).
  const uint64_t copied = answer_value([&] {
    uint64_t bytes = 0;
    m_memory->begin_batch();
    for (uint32_t r : regions) {
      const Region& reg = m_map->region(r);
      bytes += m_memory->preallocate(reg.base, reg.bytes, gpm, t);
    }
    return bytes;
  });
  answer_traffic(t, [] {});
  if (copied == 0) return -1;
  // The copies' DRAM reads and writes and their links.
  TimelineUnit info;
  info.kind = TimelineUnit::Kind::prealloc;
  info.gpm = gpm;
  return add_movement(m_machine->demand(gpm, WorkCounts{}, t), std::move(after), m_memory_spec.link_latency.value, info);
}

void FrameSim::mark_span(std::string name, std::string category, int gpm, int first, int last,
                         std::vector<std::pair<std::string, double>> args) {
  if (!keeps_timeline()) return;
  gpm_arg(gpm, "mark_span");
  unit_arg(first, "mark_span", "first");
  unit_arg(last, "mark_span", "last");
  TimelineMark m;
  m.name = std::move(name);
  m.category = std::move(category);
  m.gpm = gpm;
  m.args = std::move(args);
  m_spans.push_back({std::move(m), first, last});
}

void FrameSim::mark_instant(std::string name, std::string category, int gpm, std::vector<std::pair<std::string, double>> args) {
  if (!keeps_timeline()) return;
  gpm_arg(gpm, "mark_instant");
  TimelineMark m;
  m.name = std::move(name);
  m.category = std::move(category);
  m.gpm = gpm;
  m.start = m_engine.now();
  m.args = std::move(args);
  m_instants.push_back(std::move(m));
}

int FrameSim::compose(int gpm, std::span<const TileWork* const> records, uint64_t pixels, std::vector<int> after) {
  gpm_arg(gpm, "compose");
  after_arg(after, "compose");
  if (m_ledger)
    for (const TileWork* r : records) m_ledger->composed(*r);
  WorkCounts w;
  w.composed = pixels;
  TimelineUnit info;
  info.kind = TimelineUnit::Kind::compose;
  return add(gpm, w, empty_traffic(), std::move(after), info, false);
}

SchemeResult FrameSim::finish(const std::string& scheme, int frames_in_flight, const std::function<void(int)>& on_finish) {
  if (frames_in_flight < 1 || size_t(frames_in_flight) > m_in.frames.size())
    throw Error(named("finish", "frames_in_flight", frames_in_flight) + "frames_in_flight must be 1 to the frames given (" +
                std::to_string(m_in.frames.size()) + ")");
  const TimingEngine::Result r = m_engine.run(on_finish);
  SchemeResult& s = m_result;
  s.scheme = scheme;
  s.gpms = gpms();
  s.frequency_hz = m_timing_spec.frequency.value;
  s.frames_in_flight = frames_in_flight;
  s.frame_latency_s = r.makespan;
  // The configuration the run read: the machine's keys and its scheme's own.
  s.config = scheme_entries(scheme, s.config);
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
  // The owners logged in replay order, as one entry a key: the last GPM
  // that shaded it (a stable sort keeps the log's order within a key; a
  // comparison sort of the log was 2.5% of the paper's sweep's
  // instructions).
  stable_sort_by_pair(m_owner_log);
  s.owner.clear();
  for (size_t i = 0; i < m_owner_log.size(); ++i)
    if (i + 1 == m_owner_log.size() || m_owner_log[i + 1].first != m_owner_log[i].first) s.owner.push_back(m_owner_log[i]);
  // This frame's traffic: the totals since it began; the footprint; the
  // memory system's statistics since the frame began (or all of them, as
  // the recording read them).
  mix({kFinish});
  if (m_playing) {
    const MemoryTape::FrameEnd& e = m_playing->frame_end(m_calls);
    s.inter_gpm_bytes = e.inter_gpm_bytes;
    s.local_dram_bytes = e.local_dram_bytes;
    s.footprint_bytes = e.footprint_bytes;
    s.stats = e.stats;
    if (e.tile_inter_gpm_bytes.size() != s.tile_inter_gpm_bytes.size())
      throw TapeMismatch("the recording's frame has another number of tiles");
    s.tile_inter_gpm_bytes = e.tile_inter_gpm_bytes;
  } else {
    const TrafficTotals& t = m_memory->totals();
    for (int c = 0; c < kCategories; ++c)
      s.inter_gpm_bytes[size_t(c)] = t.inter_gpm_bytes[size_t(c)] - m_before.inter_gpm_bytes[size_t(c)];
    s.local_dram_bytes = 0;
    for (int g = 0; g < gpms(); ++g)
      for (int c = 0; c < kCategories; ++c)
        s.local_dram_bytes += t.dram_read_bytes[size_t(g)][size_t(c)] - m_before.dram_read_bytes[size_t(g)][size_t(c)] +
                              t.dram_write_bytes[size_t(g)][size_t(c)] - m_before.dram_write_bytes[size_t(g)][size_t(c)];
    s.footprint_bytes = m_memory->footprint_bytes();
    Stats now;
    m_memory->report(now);
    s.stats = now.since(m_stats_before);
    if (m_recording)
      m_recording->frame_end(m_calls,
                             {s.inter_gpm_bytes, s.local_dram_bytes, s.footprint_bytes, s.stats, s.tile_inter_gpm_bytes});
  }
  if (m_in.carried) m_in.carried->calls = m_calls;
  m_engine.report(r, s.stats);
  // Never seen so far; said when it happens rather than hidden.
  if (m_engine.unconverged())
    s.notes.push_back(std::to_string(m_engine.unconverged()) +
                      " resource sharings stopped at the iteration limit: their rates fit the resources but may leave some idle");
  if (m_in.spec->timeline) {
    s.timeline = m_unit_info;
    for (size_t i = 0; i < s.timeline.size() && i < r.units.size(); ++i) {
      s.timeline[i].start = r.units[i].start;
      s.timeline[i].work_done = r.units[i].work_done;
      s.timeline[i].finish = r.units[i].finish;
    }
    s.marks = m_instants;
    for (const PendingSpan& p : m_spans) {
      TimelineMark m = p.mark;
      m.start = r.units[size_t(p.first)].start;
      m.finish = std::max(m.start, r.units[size_t(p.last)].finish);
      s.marks.push_back(std::move(m));
    }
  }
  if (m_ledger) {
    m_ledger->check(scheme, frames_in_flight);
    s.laws_checked = true;
  }
  return s;
}

}  // namespace oovr
