// Inter-GPM topologies: directed links between nodes (GPMs 0..gpms-1, then
// any switches), and the route (list of links) between every pair of GPMs.
// A topology only adds its links; routes are the shortest paths, found by
// breadth-first search in link order, so ties are broken the same way on
// every run. One file per topology in impl/, registered by name.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "oovr/core/registry.h"

namespace oovr {

struct Link {
  int from = 0, to = 0;  // node ids
};

class Topology {
 public:
  virtual ~Topology() = default;
  int gpms() const { return m_gpms; }
  int nodes() const { return m_nodes; }
  const std::vector<Link>& links() const { return m_links; }
  // Links from GPM `from` to GPM `to`, in order; empty when from == to.
  const std::vector<int>& route(int from, int to) const { return m_routes[size_t(from * m_gpms + to)]; }
  std::string node_name(int node) const;
  std::string link_name(int link) const;  // e.g. "gpm1->gpm0"
  // The link's location in statistics: "link[1->0]", "link[2->switch0]".
  std::string link_location(int link) const;

 protected:
  Topology(int gpms, int switches) : m_gpms(gpms), m_nodes(gpms + switches) {}
  void add_link(int from, int to) { m_links.push_back({from, to}); }
  // Computes every route; call once after adding the links.
  void finish();

 private:
  int m_gpms, m_nodes;
  std::vector<Link> m_links;
  std::vector<std::vector<int>> m_routes;
};

struct TopologyFactory {
  std::string description;
  std::function<std::unique_ptr<Topology>(int gpms)> make;
};
using Topologies = Registry<TopologyFactory>;

}  // namespace oovr
