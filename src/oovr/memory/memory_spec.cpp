#include "oovr/memory/memory_spec.h"

#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/memory/placement/i_placement.h"
#include "oovr/memory/replacement/i_replacement.h"
#include "oovr/memory/topology/i_topology.h"

namespace oovr {
namespace {

bool power_of_two(uint64_t v) { return v && !(v & (v - 1)); }

// Far above any quoted figure (250 pJ a bit between nodes), so that no
// energy computed from one overflows.
constexpr Joules kMaxEnergyPerBit{1e-6};

// `max`: the largest size simulated; every instance (an L1 per SM) holds a
// tag per line, so a size without bound is memory without bound
// (cache.l1.size=1GB once ended in std::bad_alloc). Real GPUs' largest are
// tens of MB (H100's L2: 50 MB).
CacheSpec cache(const Config& c, const std::string& prefix, const CacheSpec& def, Bytes line, Bytes max) {
  CacheSpec s;
  s.size = c.get_bytes(prefix + ".size", def.size);
  if (s.size.value > max.value)
    throw Error("configuration key '" + prefix + ".size' must be at most " + format_bytes(max) + ", not " + format_bytes(s.size));
  s.ways = int(c.get_int(prefix + ".ways", def.ways, 1, 1024));
  s.replacement = c.get_choice(prefix + ".replacement", def.replacement, ReplacementPolicies::names());
  s.latency = c.get_time(prefix + ".latency", def.latency);
  s.energy_per_bit = c.get_energy(prefix + ".energy_per_bit", def.energy_per_bit, kMaxEnergyPerBit);
  if (!(s.latency.value >= 0 && s.latency.value <= 1e-3))
    throw Error("configuration key '" + prefix + ".latency' must be from 0 to 1 ms");
  const uint64_t lines = s.size.value / line.value;
  if (s.size.value % line.value != 0 || lines == 0 || lines % uint64_t(s.ways) != 0 || !power_of_two(lines / uint64_t(s.ways)))
    throw Error("configuration key '" + prefix + ".size' (" + format_bytes(s.size) +
                ") must hold a power-of-two number of sets of " + std::to_string(s.ways) + " ways of " + format_bytes(line) +
                " lines");
  return s;
}

}  // namespace

MemorySpec MemorySpec::from_config(const Config& c) {
  MemorySpec d;
  MemorySpec s;
  s.gpms = int(c.get_int("gpms", d.gpms, 1, kMaxGpms));
  s.sms_per_gpm = int(c.get_int("gpm.sms", d.sms_per_gpm, 1, 1024));
  s.line = c.get_bytes("memory.line", d.line);
  if (!power_of_two(s.line.value) || s.line.value < 32 || s.line.value > 1024)
    throw Error("configuration key 'memory.line' must be a power of two from 32 B to 1 KB, not " + format_bytes(s.line));
  s.page = c.get_bytes("memory.page", d.page);
  if (!power_of_two(s.page.value) || s.page.value < s.line.value || s.page.value > (1ull << 30))
    throw Error("configuration key 'memory.page' must be a power of two from the line size to 1 GB, not " + format_bytes(s.page));
  s.placement = c.get_choice("memory.placement", d.placement, PlacementPolicies::names());
  s.l1 = cache(c, "cache.l1", d.l1, s.line, Bytes{uint64_t(16) << 20});
  s.l2 = cache(c, "cache.l2", d.l2, s.line, Bytes{uint64_t(256) << 20});
  s.remote = cache(c, "cache.remote", d.remote, s.line, Bytes{uint64_t(256) << 20});
  s.remote_invalidate = c.get_choice("cache.remote.invalidate", d.remote_invalidate, {"draw", "frame", "never"});
  s.dram_bandwidth = c.get_bandwidth("dram.bandwidth", d.dram_bandwidth);
  s.dram_latency = c.get_time("dram.latency", d.dram_latency);
  s.link_bandwidth = c.get_bandwidth("link.bandwidth", d.link_bandwidth);
  s.link_latency = c.get_time("link.latency", d.link_latency);
  s.topology = c.get_choice("link.topology", d.topology, Topologies::names());
  // Wide physical bounds, so that no time computed from them overflows.
  for (const auto& [key, b] : {std::pair{"dram.bandwidth", s.dram_bandwidth}, std::pair{"link.bandwidth", s.link_bandwidth}})
    if (!(b.value >= 1e6 && b.value <= 1e16))
      throw Error(std::string("configuration key '") + key + "' must be from 1 MB/s to 10000 TB/s, not " + format_bandwidth(b));
  for (const auto& [key, t] : {std::pair{"dram.latency", s.dram_latency}, std::pair{"link.latency", s.link_latency}})
    if (!(t.value >= 0 && t.value <= 1e-3)) throw Error(std::string("configuration key '") + key + "' must be from 0 to 1 ms");
  s.dram_capacity = c.get_bytes("dram.capacity", d.dram_capacity);
  if (s.dram_capacity.value < s.page.value || s.dram_capacity.value > (uint64_t(1) << 44))
    throw Error("configuration key 'dram.capacity' must be from a page (" + format_bytes(s.page) + ") to 16 TB, not " +
                format_bytes(s.dram_capacity));
  s.copy_capacity = c.get_bytes("memory.copies.capacity", d.copy_capacity);
  if (s.copy_capacity.value != 0 && s.copy_capacity.value < s.page.value)
    throw Error("configuration key 'memory.copies.capacity' must be 0 (no limit) or at least a page (" + format_bytes(s.page) +
                "), not " + format_bytes(s.copy_capacity));
  s.copy_eviction = c.get_choice("memory.copies.eviction", d.copy_eviction, {"lru", "fifo"});
  s.link_energy_per_bit = c.get_energy("link.energy_per_bit", d.link_energy_per_bit, kMaxEnergyPerBit);
  s.dram_energy_per_bit = c.get_energy("dram.energy_per_bit", d.dram_energy_per_bit, kMaxEnergyPerBit);
  return s;
}

namespace {

std::vector<ConfigKey> cache_keys(const std::string& prefix, const std::string& what) {
  return {{prefix + ".size", what + ": capacity"},
          {prefix + ".ways", what + ": associativity"},
          {prefix + ".replacement", what + ": replacement policy (memory/replacement/impl)"},
          {prefix + ".latency", what + ": time from a request to its data on a hit"},
          {prefix + ".energy_per_bit", what + ": energy per bit of a lookup's line (docs/model.md, Energy)"}};
}

std::vector<ConfigKey> memory_keys() {
  std::vector<ConfigKey> k = {
      {"gpms", "GPU modules (GPMs) of the machine (Table 1: 4)"},
      {"gpm.sms", "SMs per GPM, each with its own L1 (Table 1: 8)"},
      {"memory.line", "cache line and transfer size"},
      {"memory.page", "placement granularity: each page has one home GPM"},
      {"memory.placement", "placement policy giving each page its home (memory/placement/impl)"},
      {"cache.remote.invalidate", "when remote caches drop their lines: at each draw's end, each frame's end, or never"},
      {"dram.bandwidth", "each GPM's local DRAM bandwidth (Table 1: 1 TB/s)"},
      {"dram.latency", "a DRAM access beyond the L2 (assumed: 100 cycles)"},
      {"dram.capacity", "each GPM's DRAM: homes first, OO-VR's copies in what they leave (GTX 1080: 8 GB)"},
      {"link.bandwidth", "each inter-GPM link, per direction (Table 1: 64 GB/s NVLink)"},
      {"link.latency", "one way, per hop (assumed)"},
      {"link.topology", "how GPMs are joined (memory/topology/impl)"},
      {"link.energy_per_bit", "energy per bit a link carries (the paper's citation: 10pJ on a board, 250pJ between nodes)"},
      {"dram.energy_per_bit", "energy per bit read or written in a GPM's DRAM (GDDR5: 14pJ; HBM2: 3.97pJ)"},
      {"memory.copies.capacity", "a cap on the copies each GPM keeps ahead of use, for studies (0: none but the DRAM)"},
      {"memory.copies.eviction", "which copy gives way when copies need room: least recently used or oldest"}};
  for (auto [prefix, what] : {std::pair{"cache.l1", "L1 per SM"}, std::pair{"cache.l2", "L2 per GPM"},
                              std::pair{"cache.remote", "remote cache per GPM (MCM-GPU's L1.5)"}})
    for (ConfigKey& x : cache_keys(prefix, what)) k.push_back(std::move(x));
  return k;
}

const ConfigSections::Add reg("memory", {"the memory system: GPMs, caches, DRAM, links, placement and copies",
                                         [](const Config& c) { (void)MemorySpec::from_config(c); }, memory_keys()});

}  // namespace

}  // namespace oovr
