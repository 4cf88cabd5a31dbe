#pragma once
// Bridges between groups of crack lines (step 4 of the consistent extraction, thesis Fig. 4.8b, c;
// crack2d/consistent_extraction.hpp). The working graph's nodes are the Voronoi nodes of one extraction
// and the vertices of the previous crack; its edges are the Voronoi edges inside the damaged region and
// straight links to old vertices. A group is a set of nodes joined by crack lines: a component of the
// previous crack or a piece of new lines. A new group is joined to the nearest other group by a shortest
// path through the working graph, unless an old tip of another group is reachable for a little more: a
// crack grows from its tip (Fig. 4.8b), and joining the stem behind the tip would leave the last stretch
// of the old crack as a dangling tongue beside the new line.
#include "core/union_find.hpp"

#include <cstddef>
#include <vector>

namespace shellfrac::crack2d {

struct WorkingEdge {
  int to;
  double length;
  int voronoi_edge;  // index into VoronoiGraph::edges, or -1 for a straight link to an old vertex
};

// One step of a bridge, between two working nodes.
struct BridgeLink {
  int from, to;
  int voronoi_edge;  // as in WorkingEdge
};

struct BridgeSettings {
  double max_length = 0.0;      // longest path accepted as a bridge
  double tip_preference = 0.0;  // a path to a preferred tip may be this much longer than the shortest
};

class GroupBridges {
 public:
  // All per working node. active: the node lies on a group; has_old (per group root): the group holds
  // previous crack; old_end: a vertex of degree 1 of the previous crack (a bridge to it from a group
  // holding previous crack is a tip bridge); preferred_tip: an old_end inside the patch, preferred as a
  // target. groups, active and has_old are updated as bridges merge groups; all references must outlive
  // this object.
  GroupBridges(const std::vector<std::vector<WorkingEdge>>& adjacency, core::UnionFind& groups,
               std::vector<char>& active, std::vector<char>& has_old, std::vector<char> old_end,
               std::vector<char> preferred_tip, const BridgeSettings& settings);

  // Bridges the group of `node` to other groups while one is reachable, so a crack that runs into two
  // older ones (merging, Fig. 4.8c) joins both; every bridge merges two groups, so this terminates.
  // Appends the steps of each bridge to links (target first).
  void bridge_group_of(int node, std::vector<BridgeLink>& links);

  size_t tip_bridges() const { return tip_bridges_; }    // bridges to an old tip
  size_t branch_links() const { return branch_links_; }  // bridges to another group elsewhere

 private:
  bool bridge_from(std::size_t root, std::vector<BridgeLink>& links);
  int nearest_target(std::size_t root);
  void add_bridge(std::size_t root, int target, std::vector<BridgeLink>& links);

  const std::vector<std::vector<WorkingEdge>>& adjacency_;
  core::UnionFind& groups_;
  std::vector<char>& active_;
  std::vector<char>& has_old_;
  const std::vector<char> old_end_;
  const std::vector<char> preferred_tip_;
  const BridgeSettings settings_;
  std::vector<double> dist_;  // search scratch, reset after each search
  std::vector<int> came_from_, came_by_, touched_;
  size_t tip_bridges_ = 0, branch_links_ = 0;
};

}  // namespace shellfrac::crack2d
