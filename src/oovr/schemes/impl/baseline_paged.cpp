// baseline-paged: the baseline (Section 3) with its tiles dealt by
// framebuffer page instead of one by one: an eye's blocks of tiles (the
// 8x8 tiles of one 64 KB page) go to its group's GPMs in turn
// (sort_first.h), so that first touch makes each GPM's colour and depth
// local and they never cross a link. Not the paper's baseline (which
// distributes work "without specific scheduling"): a page-aware one, to
// measure what the framebuffer's placement is worth.
//
// Derived from the trace: as baseline. Duplicates nothing.
#include "oovr/schemes/sort_first.h"

namespace oovr {
namespace {

class BaselinePaged final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    FrameSim sim(in);
    sort_first(sim, eye_groups_by_page(sim.gpms(), sim.frame(), sim.layout()), Geometry::shared);
    return sim.finish("baseline-paged");
  }
};

const Schemes::Add reg("baseline-paged", {"the baseline with tiles dealt by framebuffer page (page-aware)",
                                          [] { return std::make_unique<BaselinePaged>(); }, 30});

}  // namespace
}  // namespace oovr
