#include "oovr/timing/gpm_model.h"

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"

namespace oovr {

namespace {
// The links a unit's traffic crossed (each one a demand of its own).
size_t links_used(const UnitTraffic& t) {
  size_t n = 0;
  for (const uint64_t bytes : t.link_bytes) n += size_t(bytes != 0);
  return n;
}
}  // namespace

TimingSpec TimingSpec::from_config(const Config& c) {
  TimingSpec d, s;
  const auto positive = [&](const char* key, int def) { return int(c.get_int(key, def, 1, 1000000)); };
  s.frequency = c.get_frequency("frequency", d.frequency);
  if (!(s.frequency.value >= 1e6 && s.frequency.value <= 1e11))
    throw Error("configuration key 'frequency' must be from 1 MHz to 100 GHz");
  s.lanes_per_sm = positive("gpm.lanes", d.lanes_per_sm);
  s.texture_units_per_sm = positive("gpm.texture_units", d.texture_units_per_sm);
  s.rops = positive("gpm.rops", d.rops);
  s.rop_pixels_per_clock = positive("gpm.rop_pixels_per_clock", d.rop_pixels_per_clock);
  s.raster_fragments_per_clock = positive("gpm.raster_fragments_per_clock", d.raster_fragments_per_clock);
  s.setup_triangles_per_clock = positive("gpm.setup_triangles_per_clock", d.setup_triangles_per_clock);
  s.vertex_instructions = positive("shader.vertex_instructions", d.vertex_instructions);
  // 0: each pass's own count.
  s.fragment_instructions = int(c.get_int("shader.fragment_instructions", d.fragment_instructions, 0, 1000000));
  s.triangle_bytes = positive("shader.triangle_bytes", d.triangle_bytes);
  // 0: no limit.
  s.requests_in_flight = int(c.get_int("gpm.requests_in_flight", d.requests_in_flight, 0, 1000000));
  s.draw_cycles = c.get_double("gpm.draw_cycles", d.draw_cycles, 0, 1e9);
  s.draws_ahead = int(c.get_int("gpm.draws_ahead", d.draws_ahead, 1, 1000000));
  s.sharing = c.get_choice("timing.sharing", d.sharing == Sharing::fair ? "fair" : "equal", {"fair", "equal"}) == "fair"
                  ? Sharing::fair
                  : Sharing::equal;
  return s;
}

namespace {

const ConfigSections::Add reg(
    "timing", {"the GPMs' resources, shaders, front end and how units share resources",
               [](const Config& c) { (void)TimingSpec::from_config(c); },
               {{"frequency", "clock of every GPM (Table 1: 1 GHz)"},
                {"gpm.lanes", "shader lanes per SM (Table 1: 64)"},
                {"gpm.texture_units", "texture units per SM, one bilinear lookup per clock each (Table 1: 4)"},
                {"gpm.rops", "ROPs per GPM (Table 1: 8)"},
                {"gpm.rop_pixels_per_clock", "pixels each ROP writes per clock (Section 3: 4)"},
                {"gpm.raster_fragments_per_clock", "fragments a GPM's raster engines produce per clock (assumed)"},
                {"gpm.setup_triangles_per_clock", "triangles a GPM sets up per clock (assumed)"},
                {"gpm.requests_in_flight", "memory requests an SM keeps in flight (0: no limit)"},
                {"gpm.draw_cycles", "front-end cycles per draw a GPM receives (calibrated on an H100)"},
                {"gpm.draws_ahead", "draws a front end may run ahead of its pipeline (calibrated on an H100)"},
                {"shader.vertex_instructions", "instructions per vertex (assumed)"},
                {"shader.fragment_instructions", "instructions per fragment for every pass (0: each pass's own count)"},
                {"shader.triangle_bytes", "bytes of a set-up triangle handed to another GPM (assumed)"},
                {"timing.sharing", "how units share a resource: fair (max-min, work-conserving) or equal"}}});

}  // namespace

MachineModel::MachineModel(const TimingSpec& timing, const MemorySpec& memory, const Topology& topology, TimingEngine& engine)
    : m_timing(timing), m_memory(memory) {
  engine.set_sharing(timing.sharing);
  const double f = timing.frequency.value;
  for (int g = 0; g < memory.gpms; ++g) {
    const std::string p = "gpm[" + std::to_string(g) + "].";
    Gpm r;
    // Shader lanes run vertex and fragment instructions alike (unified shaders).
    r.shader = engine.add_resource(p + "shader", double(memory.sms_per_gpm) * timing.lanes_per_sm * f);
    r.texture = engine.add_resource(p + "texture", double(memory.sms_per_gpm) * timing.texture_units_per_sm * f);
    r.raster = engine.add_resource(p + "raster", double(timing.raster_fragments_per_clock) * f);
    r.setup = engine.add_resource(p + "setup", double(timing.setup_triangles_per_clock) * f);
    r.rop = engine.add_resource(p + "rop", double(timing.rops) * timing.rop_pixels_per_clock * f);
    r.dram = engine.add_resource(p + "dram", memory.dram_bandwidth.value, "B");
    if (timing.requests_in_flight > 0)
      r.requests = engine.add_resource(p + "requests", double(memory.sms_per_gpm) * timing.requests_in_flight, "s");
    m_gpm.push_back(r);
    m_queue.push_back(engine.add_queue("gpm[" + std::to_string(g) + "]"));
    m_front_queue.push_back(engine.add_queue("gpm[" + std::to_string(g) + "].front"));
  }
  for (size_t l = 0; l < topology.links().size(); ++l)
    m_link.push_back(engine.add_resource(topology.link_location(int(l)), memory.link_bandwidth.value, "B"));
}

std::vector<std::pair<int, double>> MachineModel::demand(int gpm, const WorkCounts& w, const UnitTraffic& t) const {
  const Gpm& r = m_gpm[size_t(gpm)];
  const double instructions =
      double(w.vertices) * m_timing.vertex_instructions + m_timing.fragment_work(w.quads, w.fragment_instructions);
  // Sized once: grown pair by pair, a unit's list was up to four
  // allocations, and a frame's replay makes thousands of units.
  size_t n = size_t(instructions > 0) + size_t(w.samples != 0) + size_t(w.covered != 0) + size_t(w.triangles != 0) +
             size_t(w.covered + w.composed != 0) + size_t(r.requests >= 0);
  for (size_t g = 0; g < t.dram_read_bytes.size(); ++g) n += size_t(t.dram_read_bytes[g] + t.dram_write_bytes[g] != 0);
  n += links_used(t);
  std::vector<std::pair<int, double>> d;
  d.reserve(n);
  if (instructions > 0) d.push_back({r.shader, instructions});
  if (w.samples) d.push_back({r.texture, double(w.samples)});
  if (w.covered) d.push_back({r.raster, double(w.covered)});
  if (w.triangles) d.push_back({r.setup, double(w.triangles)});
  if (w.covered + w.composed) d.push_back({r.rop, double(w.covered + w.composed)});
  // Every DRAM the unit read or wrote, and every link its data crossed.
  for (size_t g = 0; g < t.dram_read_bytes.size(); ++g) {
    const uint64_t bytes = t.dram_read_bytes[g] + t.dram_write_bytes[g];
    if (bytes) d.push_back({m_gpm[g].dram, double(bytes)});
  }
  for (size_t l = 0; l < t.link_bytes.size(); ++l)
    if (t.link_bytes[l]) d.push_back({m_link[l], double(t.link_bytes[l])});
  if (r.requests >= 0) {
    const double held = read_latency(t);
    if (held > 0) d.push_back({r.requests, held});
  }
  return d;
}

double MachineModel::read_latency(const UnitTraffic& t) const {
  const double l1 = m_memory.l1.latency.value, l2 = m_memory.l2.latency.value, rc = m_memory.remote.latency.value;
  const double dram = m_memory.dram_latency.value, link = m_memory.link_latency.value;
  return double(t.l1_hits) * l1 + double(t.l2_read_hits) * l2 + double(t.local_dram_reads) * (l2 + dram) +
         double(t.remote_hits) * rc + double(t.home_l2_hits) * (rc + l2) + double(t.remote_dram_reads) * (rc + l2 + dram) +
         double(t.remote_hops) * 2 * link;
}

std::vector<std::pair<int, double>> MachineModel::transfer_demand(const UnitTraffic& t) const {
  std::vector<std::pair<int, double>> d;
  d.reserve(links_used(t));
  for (size_t l = 0; l < t.link_bytes.size(); ++l)
    if (t.link_bytes[l]) d.push_back({m_link[l], double(t.link_bytes[l])});
  return d;
}

}  // namespace oovr
