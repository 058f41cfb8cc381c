#include "oovr/core/error.h"
#include "oovr/memory/placement/i_placement.h"

namespace oovr {

void PlacementPolicy::pin(uint32_t, int) { throw Error("only the pinned placement policy takes pin()"); }

}  // namespace oovr
