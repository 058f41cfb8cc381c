// fully-connected: a link in each direction between every pair of GPMs, the
// paper's 6-port point-to-point system for 4 GPMs (Table 1).
#include "oovr/memory/topology/i_topology.h"

namespace oovr {
namespace {

class FullyConnected final : public Topology {
 public:
  explicit FullyConnected(int gpms) : Topology(gpms, 0) {
    for (int a = 0; a < gpms; ++a)
      for (int b = 0; b < gpms; ++b)
        if (a != b) add_link(a, b);
    finish();
  }
};

const Topologies::Add reg("fully-connected", {"a link each way between every pair of GPMs",
                                              [](int gpms) { return std::make_unique<FullyConnected>(gpms); }});

}  // namespace
}  // namespace oovr
