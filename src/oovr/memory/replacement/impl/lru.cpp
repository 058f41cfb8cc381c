// lru: evict the least recently used line.
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {
namespace {

class Lru final : public ReplacementPolicy {
 public:
  // The first way of the oldest use. Branch-free (selects, not jumps):
  // the ages of a set's ways are in no predictable order.
  int victim(const WayState* w, int n) override {
    int v = 0;
    uint64_t oldest = w[0].last_use;
    for (int i = 1; i < n; ++i) {
      const bool older = w[i].last_use < oldest;
      oldest = older ? w[i].last_use : oldest;
      v = older ? i : v;
    }
    return v;
  }
};

const ReplacementPolicies::Add reg("lru", {"least recently used", [](uint64_t) { return std::make_unique<Lru>(); }});

}  // namespace
}  // namespace oovr
