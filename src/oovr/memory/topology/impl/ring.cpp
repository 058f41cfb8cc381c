// ring: each GPM linked both ways to its two neighbours; traffic between
// distant GPMs crosses the GPMs between (shortest way round; clockwise, to
// higher numbers, on a tie).
#include "oovr/memory/topology/i_topology.h"

namespace oovr {
namespace {

class Ring final : public Topology {
 public:
  explicit Ring(int gpms) : Topology(gpms, 0) {
    if (gpms == 2) {
      add_link(0, 1);
      add_link(1, 0);
    } else if (gpms > 2) {
      for (int g = 0; g < gpms; ++g) add_link(g, (g + 1) % gpms);
      for (int g = 0; g < gpms; ++g) add_link(g, (g + gpms - 1) % gpms);
    }
    finish();
  }
};

const Topologies::Add reg("ring",
                          {"each GPM linked to its two neighbours", [](int gpms) { return std::make_unique<Ring>(gpms); }});

}  // namespace
}  // namespace oovr
