// random: evict a pseudo-random way, from a generator seeded per cache, so
// that runs are reproducible.
#include "oovr/core/rng.h"
#include "oovr/memory/replacement/i_replacement.h"

namespace oovr {
namespace {

class Random final : public ReplacementPolicy {
 public:
  explicit Random(uint64_t seed) : m_rng(seed) {}
  int victim(const SetState& s) override { return int(m_rng.below(uint32_t(s.ways))); }

 private:
  Rng m_rng;
};

const ReplacementPolicies::Add reg("random", {"a reproducible pseudo-random way",
                                              [](uint64_t seed) { return std::make_unique<Random>(seed); }});

}  // namespace
}  // namespace oovr
