// switch: every GPM has one link to and one from a central switch (as
// NVSwitch systems); every transfer between GPMs takes two hops.
#include "oovr/memory/topology/i_topology.h"

namespace oovr {
namespace {

class Switch final : public Topology {
 public:
  explicit Switch(int gpms) : Topology(gpms, 1) {
    for (int g = 0; g < gpms; ++g) add_link(g, gpms);
    for (int g = 0; g < gpms; ++g) add_link(gpms, g);
    finish();
  }
};

const Topologies::Add reg("switch",
                          {"every GPM linked to a central switch", [](int gpms) { return std::make_unique<Switch>(gpms); }});

}  // namespace
}  // namespace oovr
