// Cache replacement policies, pluggable: one file per policy in impl/,
// registered by name. Per-line state lives in the cache (gem5's
// ReplacementData idea): every policy sees when a line was inserted and last
// used, so hits cost no virtual call and only a miss asks the policy.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "oovr/core/registry.h"

namespace oovr {

struct WayState {
  uint64_t last_use = 0;  // access counter value at the last hit or insertion
  uint64_t inserted = 0;  // access counter value at insertion
};

class ReplacementPolicy {
 public:
  virtual ~ReplacementPolicy() = default;
  // The way of a full set to evict. It may read the order of the ways'
  // counters, not their values: a read of a set's most recently used line
  // again is not counted (Cache::access returns at once), which
  // changes no order but does change the counters' values.
  virtual int victim(const WayState* ways, int n) = 0;
};

struct ReplacementFactory {
  std::string description;
  std::function<std::unique_ptr<ReplacementPolicy>(uint64_t seed)> make;
};
using ReplacementPolicies = Registry<ReplacementFactory>;

}  // namespace oovr
