#include <deque>

#include "oovr/core/error.h"
#include "oovr/memory/topology/i_topology.h"

namespace oovr {

std::string Topology::node_name(int node) const {
  return node < m_gpms ? "gpm" + std::to_string(node) : "switch" + std::to_string(node - m_gpms);
}

std::string Topology::link_name(int link) const {
  const Link& l = m_links[size_t(link)];
  return node_name(l.from) + "->" + node_name(l.to);
}

std::string Topology::link_location(int link) const {
  const Link& l = m_links[size_t(link)];
  const auto node = [&](int n) { return n < m_gpms ? std::to_string(n) : node_name(n); };
  return "link[" + node(l.from) + "->" + node(l.to) + "]";
}

void Topology::finish() {
  m_routes.assign(size_t(m_gpms) * size_t(m_gpms), {});
  for (int src = 0; src < m_gpms; ++src) {
    // Breadth-first search from src; `via[n]` is the link that reached n.
    std::vector<int> via(size_t(m_nodes), -1);
    std::vector<bool> seen(size_t(m_nodes), false);
    std::deque<int> queue{src};
    seen[size_t(src)] = true;
    while (!queue.empty()) {
      const int n = queue.front();
      queue.pop_front();
      for (size_t l = 0; l < m_links.size(); ++l)
        if (m_links[l].from == n && !seen[size_t(m_links[l].to)]) {
          seen[size_t(m_links[l].to)] = true;
          via[size_t(m_links[l].to)] = int(l);
          queue.push_back(m_links[l].to);
        }
    }
    for (int dst = 0; dst < m_gpms; ++dst) {
      if (dst == src) continue;
      if (!seen[size_t(dst)]) throw Error("topology: no route from " + node_name(src) + " to " + node_name(dst));
      std::vector<int>& r = m_routes[size_t(src * m_gpms + dst)];
      for (int n = dst; n != src; n = m_links[size_t(via[size_t(n)])].from) r.insert(r.begin(), via[size_t(n)]);
    }
  }
}

}  // namespace oovr
