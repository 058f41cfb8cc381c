// first-touch: the first GPM to touch a page becomes its home (MCM-GPU,
// ISCA 2017; the paper's baseline, Section 3).
#include "oovr/memory/placement/i_placement.h"

namespace oovr {
namespace {

class FirstTouch final : public PlacementPolicy {
 public:
  int assign(uint64_t, uint32_t, int requester) override { return requester; }
};

const PlacementPolicies::Add reg("first-touch", {"the first GPM to touch a page is its home",
                                                 [](int) { return std::make_unique<FirstTouch>(); }});

}  // namespace
}  // namespace oovr
