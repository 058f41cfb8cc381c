// lru: evict the least recently used line.
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {
namespace {

class Lru final : public ReplacementPolicy {
 public:
  // The first way of the oldest use. Branch-free (selects, not jumps):
  // the ages of a set's ways are in no predictable order.
  int victim(const SetState& s) override {
    const uint32_t* use = s.last_use;
    int v = 0;
    uint32_t oldest = use[0];
    for (int i = 1; i < s.ways; ++i) {
      const bool older = use[i] < oldest;
      oldest = older ? use[i] : oldest;
      v = older ? i : v;
    }
    return v;
  }
};

// Caches keep an LRU set's ways in their order of use (least_recently_used)
// and take its last; victim() answers for any other user of the policy.
const ReplacementPolicies::Add reg("lru", {"least recently used", [](uint64_t) { return std::make_unique<Lru>(); }, true});

}  // namespace
}  // namespace oovr
