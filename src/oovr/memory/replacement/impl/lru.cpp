// lru: evict the least recently used line.
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {
namespace {

class Lru final : public ReplacementPolicy {
 public:
  int victim(const WayState* w, int n) override {
    int v = 0;
    for (int i = 1; i < n; ++i)
      if (w[i].last_use < w[v].last_use) v = i;
    return v;
  }
};

const ReplacementPolicies::Add reg("lru", {"least recently used", [](uint64_t) { return std::make_unique<Lru>(); }});

}  // namespace
}  // namespace oovr
