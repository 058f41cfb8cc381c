// fifo: evict the line inserted first, whatever its use since.
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {
namespace {

class Fifo final : public ReplacementPolicy {
 public:
  int victim(const SetState& s) override {
    int v = 0;
    for (int i = 1; i < s.ways; ++i)
      if (s.inserted[i] < s.inserted[v]) v = i;
    return v;
  }
};

const ReplacementPolicies::Add reg("fifo", {"first in, first out", [](uint64_t) { return std::make_unique<Fifo>(); }});

}  // namespace
}  // namespace oovr
