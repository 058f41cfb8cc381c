// replicated: every GPM holds its own copy of every page (what AFR and
// distributed parallel-rendering frameworks do, Section 2.3); all reads are
// local, and the memory footprint is multiplied by the GPM count.
#include "oovr/memory/placement/i_placement.h"

namespace oovr {
namespace {

class Replicated final : public PlacementPolicy {
 public:
  int assign(uint64_t, uint32_t, int requester) override { return requester; }
  bool replicate_all() const override { return true; }
};

const PlacementPolicies::Add reg("replicated",
                                 {"every GPM holds a copy of every page", [](int) { return std::make_unique<Replicated>(); }});

}  // namespace
}  // namespace oovr
