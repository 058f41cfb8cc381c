// interleaved: pages round-robin over the GPMs by page number, whoever
// touches them (the usual NUMA default when locality is unknown).
#include "oovr/memory/placement/i_placement.h"

namespace oovr {
namespace {

class Interleaved final : public PlacementPolicy {
 public:
  explicit Interleaved(int gpms) : m_gpms(gpms) {}
  int assign(uint64_t page, uint32_t, int) override { return int(page % uint64_t(m_gpms)); }

 private:
  int m_gpms;
};

const PlacementPolicies::Add reg("interleaved", {"pages round-robin over the GPMs",
                                                 [](int gpms) { return std::make_unique<Interleaved>(gpms); }});

}  // namespace
}  // namespace oovr
