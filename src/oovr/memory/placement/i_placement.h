// Page placement policies (DESIGN.md, "How work becomes time"): which GPM's
// DRAM is a page's home. One file per policy in impl/, registered by name.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "oovr/core/registry.h"

namespace oovr {

class PlacementPolicy {
 public:
  virtual ~PlacementPolicy() = default;
  // The home of a page nobody has touched yet, now touched by `requester`.
  // `region` is the address-map region the page belongs to.
  virtual int assign(uint64_t page, uint32_t region, int requester) = 0;
  // True when every GPM holds a copy of every page (replication).
  virtual bool replicate_all() const { return false; }
  // Names the home of a region's pages. Only the pinned policy accepts it;
  // the others throw Error.
  virtual void pin(uint32_t region, int gpm);
};

struct PlacementFactory {
  std::string description;
  std::function<std::unique_ptr<PlacementPolicy>(int gpms)> make;
};
using PlacementPolicies = Registry<PlacementFactory>;

}  // namespace oovr
