#include "crack2d/medial_spurs.hpp"

#include <cstddef>

namespace shellfrac::crack2d {

int prune_spurs(const std::vector<std::array<int, 2>>& edge_nodes, const std::vector<double>& edge_length,
                std::vector<char>& keep, const std::vector<char>& anchored, const std::vector<double>& node_radius,
                double min_protrusion) {
  const size_t nodes = anchored.size();
  std::vector<std::vector<int>> incident(nodes);
  for (size_t e = 0; e < edge_nodes.size(); ++e) {
    if (!keep[e] || edge_nodes[e][0] == edge_nodes[e][1]) continue;
    incident[edge_nodes[e][0]].push_back(static_cast<int>(e));
    incident[edge_nodes[e][1]].push_back(static_cast<int>(e));
  }
  auto other = [&](int e, int k) { return edge_nodes[e][0] == k ? edge_nodes[e][1] : edge_nodes[e][0]; };
  std::vector<int> pruned_edges, chain;
  int pruned = 0;
  for (size_t t = 0; t < nodes; ++t) {
    if (incident[t].size() != 1 || anchored[t]) continue;
    // Walk from the tip over nodes of degree 2 to the first junction, end or anchored node.
    chain.assign(1, incident[t][0]);
    double length = edge_length[incident[t][0]];
    int current = other(incident[t][0], static_cast<int>(t));
    int came_by = incident[t][0];
    while (incident[current].size() == 2 && !anchored[current] && current != static_cast<int>(t)) {
      const int next = incident[current][0] == came_by ? incident[current][1] : incident[current][0];
      chain.push_back(next);
      length += edge_length[next];
      came_by = next;
      current = other(next, current);
    }
    if (incident[current].size() < 3 || anchored[current]) continue;  // a whole line, or a continuation of the crack
    if (length + node_radius[t] - node_radius[current] >= min_protrusion) continue;
    pruned_edges.insert(pruned_edges.end(), chain.begin(), chain.end());
    ++pruned;
  }
  for (int e : pruned_edges) keep[e] = 0;
  return pruned;
}

}  // namespace shellfrac::crack2d
