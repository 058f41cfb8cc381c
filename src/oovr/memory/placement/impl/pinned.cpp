// pinned: the caller names each region's home GPM (pin()); touching a page
// of a region nobody pinned is an error, never a silent default.
#include <map>

#include "oovr/core/error.h"
#include "oovr/memory/placement/i_placement.h"

namespace oovr {
namespace {

class Pinned final : public PlacementPolicy {
 public:
  explicit Pinned(int gpms) : m_gpms(gpms) {}
  int assign(uint64_t page, uint32_t region, int) override {
    const auto it = m_home.find(region);
    if (it == m_home.end())
      throw Error("pinned placement: page " + std::to_string(page) + " of region " + std::to_string(region) +
                  " was touched before its region was pinned to a GPM");
    return it->second;
  }
  void pin(uint32_t region, int gpm) override {
    if (gpm < 0 || gpm >= m_gpms) throw Error("pinned placement: GPM " + std::to_string(gpm) + " does not exist");
    m_home[region] = gpm;
  }

 private:
  int m_gpms;
  std::map<uint32_t, int> m_home;
};

const PlacementPolicies::Add reg("pinned", {"the caller names each region's home",
                                            [](int gpms) { return std::make_unique<Pinned>(gpms); }});

}  // namespace
}  // namespace oovr
