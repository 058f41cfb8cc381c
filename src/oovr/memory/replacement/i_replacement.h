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

// A full set's ways, as the cache keeps them: per way, the access counter's
// value at its line's last hit or insertion, and at its insertion.
struct SetState {
  const uint32_t* last_use;
  const uint32_t* inserted;
  int ways;
};

class ReplacementPolicy {
 public:
  virtual ~ReplacementPolicy() = default;
  // The way of a full set to evict. It may read the order of the ways'
  // counters within the set, not their values: a read of a set's most
  // recently used line again is not counted (Cache::access returns at
  // once), which changes no order but does change the counters' values; and
  // the cache renumbers the counters when they would wrap, keeping each
  // set's order.
  virtual int victim(const SetState& set) = 0;
};

struct ReplacementFactory {
  std::string description;
  std::function<std::unique_ptr<ReplacementPolicy>(uint64_t seed)> make;
  // True for a policy that always evicts the least recently used way: the
  // ways' order of use is all it reads, so the cache keeps each set's ways
  // in that order and never asks victim() (Cache's recency-ordered sets).
  bool least_recently_used = false;
};
using ReplacementPolicies = Registry<ReplacementFactory>;

}  // namespace oovr
