// preallocated: data is copied ahead of use onto the GPM that will need it
// (OO-VR's pre-allocation units, Section 5.2). The copies are made by
// MemorySystem::preallocate, which counts their bytes as link traffic of
// category prealloc; pages nobody pre-allocated fall back to first touch.
#include "oovr/memory/placement/i_placement.h"

namespace oovr {
namespace {

class Preallocated final : public PlacementPolicy {
 public:
  int assign(uint64_t, uint32_t, int requester) override { return requester; }
};

const PlacementPolicies::Add reg("preallocated", {"copies made ahead of use by preallocate(); first touch otherwise",
                                                  [](int) { return std::make_unique<Preallocated>(); }});

}  // namespace
}  // namespace oovr
