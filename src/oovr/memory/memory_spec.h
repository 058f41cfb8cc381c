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
};

struct MemorySpec {
  int gpms = 4;          // GPU modules (Table 1)
  int sms_per_gpm = 8;   // SMs per GPM (Table 1), one L1 each
  Bytes line{128};       // cache line
  Bytes page{64 << 10};  // placement granularity
  std::string placement = "first-touch";
  CacheSpec l1{{128 << 10}, 4, "lru"};       // per SM (Table 1: 128 KB)
  CacheSpec l2{{1 << 20}, 16, "lru"};        // per GPM (Table 1: 4 MB total, 16-way)
  CacheSpec remote{{1 << 20}, 16, "lru"};    // per GPM, lines homed elsewhere (MCM-GPU's L1.5)
  std::string remote_invalidate = "frame";   // draw, frame or never
  BytesPerSecond dram_bandwidth{1e12};       // per GPM (Table 1: 1 TB/s)
  Seconds dram_latency{100e-9};
  BytesPerSecond link_bandwidth{64e9};       // per direction per GPM pair (Table 1: 64 GB/s)
  Seconds link_latency{32e-9};
  std::string topology = "fully-connected";  // fully-connected, ring or switch

  // Reads every memory key of `c` (defaults above for missing ones) and
  // checks the values. Throws Error naming a bad key.
  static MemorySpec from_config(const Config& c);
};

}  // namespace oovr
