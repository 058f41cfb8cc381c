// The memory system's configuration (the paper's Table 1 by default), read
// from the configuration tree. Every default is documented in docs/model.md
// with its source.
#pragma once

#include <string>

#include "oovr/core/config.h"
#include "oovr/core/units.h"

namespace oovr {

struct CacheSpec {
  Bytes size;
  int ways = 16;
  std::string replacement = "lru";
  Seconds latency{0};  // from a request to its data, for a hit in this cache
  // Each lookup reads or writes a line in the cache's arrays: a cited
  // per-access energy divided by the bits it moved (docs/model.md, "Energy").
  Joules energy_per_bit{0};
};

// The most GPMs a machine may have (configuration key gpms).
constexpr int kMaxGpms = 32;

struct MemorySpec {
  int gpms = 4;          // GPU modules (Table 1)
  int sms_per_gpm = 8;   // SMs per GPM (Table 1), one L1 each
  Bytes line{128};       // cache line
  Bytes page{64 << 10};  // placement granularity
  std::string placement = "first-touch";
  // Latencies: Accel-Sim's TITAN X (Pascal) model has 82 cycles of L1 hit;
  // an L2 hit (and a remote-cache hit, a lookup of the same kind) is
  // assumed at 200 cycles, all at Table 1's 1 GHz.
  //
  // Energies (docs/model.md, "Energy"): an L1 access of 32 B about 56 pJ
  // (Keckler et al., IEEE Micro 2011, Table 1: 14 pJ per 64-bit read of an
  // 8 KB SRAM), an L2 access of 32 B about 400 pJ (Dally, Hot Chips 2023),
  // each per bit (/ 256: 0.21875 and 1.5625 pJ); the remote cache is an
  // SRAM of the L2's kind.
  CacheSpec l1{{128 << 10}, 4, "lru", {82e-9}, {0.21875 / 1e12}};     // per SM (Table 1: 128 KB)
  CacheSpec l2{{1 << 20}, 16, "lru", {200e-9}, {1.5625 / 1e12}};      // per GPM (Table 1: 4 MB total, 16-way)
  CacheSpec remote{{1 << 20}, 16, "lru", {200e-9}, {1.5625 / 1e12}};  // per GPM, lines homed elsewhere (MCM-GPU's L1.5)
  std::string remote_invalidate = "frame";                            // draw, frame or never
  BytesPerSecond dram_bandwidth{1e12};                                // per GPM (Table 1: 1 TB/s)
  // Per GPM. The paper gives no capacity; its GPM "resembles" NVIDIA's
  // Pascal GTX 1080 (Sections 2 and 3 cite it), which has 8 GB of GDDR5X.
  Bytes dram_capacity{uint64_t(8) << 30};
  Seconds dram_latency{100e-9};              // beyond the L2 (assumed; Accel-Sim's dram_latency: 100 cycles)
  BytesPerSecond link_bandwidth{64e9};       // per direction per GPM pair (Table 1: 64 GB/s)
  Seconds link_latency{32e-9};               // one way, per hop (assumed)
  std::string topology = "fully-connected";  // fully-connected, ring or switch
  // Energy per bit moved, integrated over the bytes counted. Links: 10 pJ
  // on a board, as the paper cites (Section 1, from MCM-GPU, ISCA 2017,
  // Table 2: 0.5 pJ on a package, 10 on a board, 250 between nodes). DRAM:
  // 14 pJ per bit read or written (GDDR5; O'Connor et al., MICRO 2017,
  // Fig. 1a; HBM2 3.97 pJ), standing in for the GTX 1080's GDDR5X.
  Joules link_energy_per_bit{10e-12};
  Joules dram_energy_per_bit{14e-12};
  // Copies made ahead of use (pre-allocation, Section 5.2) live in "unused
  // DRAM": what the GPM's homes leave of dram_capacity, the least recently
  // used (or the oldest, "fifo") dropped to make room. copy_capacity caps
  // them further, for studies (0: no cap but the DRAM).
  Bytes copy_capacity{0};
  std::string copy_eviction = "lru";

  // Reads every memory key of `c` (defaults above for missing ones) and
  // checks the values. Throws Error naming a bad key.
  static MemorySpec from_config(const Config& c);
};

}  // namespace oovr
