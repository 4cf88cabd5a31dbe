#include "crack2d/group_bridges.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace shellfrac::crack2d {

GroupBridges::GroupBridges(const std::vector<std::vector<WorkingEdge>>& adjacency, core::UnionFind& groups,
                           std::vector<char>& active, std::vector<char>& has_old, std::vector<char> old_end,
                           std::vector<char> preferred_tip, const BridgeSettings& settings)
    : adjacency_(adjacency),
      groups_(groups),
      active_(active),
      has_old_(has_old),
      old_end_(std::move(old_end)),
      preferred_tip_(std::move(preferred_tip)),
      settings_(settings),
      dist_(adjacency.size(), std::numeric_limits<double>::infinity()),
      came_from_(adjacency.size(), -1),
      came_by_(adjacency.size(), -1) {}

void GroupBridges::bridge_group_of(int node, std::vector<BridgeLink>& links) {
  while (bridge_from(groups_.find(node), links)) {
  }
}

// One bridge from group `root` to the group nearest_target() finds, if any; resets the search scratch.
bool GroupBridges::bridge_from(std::size_t root, std::vector<BridgeLink>& links) {
  const int target = nearest_target(root);
  if (target >= 0) add_bridge(root, target, links);
  for (int k : touched_) {
    dist_[k] = std::numeric_limits<double>::infinity();
    came_from_[k] = came_by_[k] = -1;
  }
  touched_.clear();
  return target >= 0;
}

// Shortest paths (Dijkstra, up to settings_.max_length) from every node of group `root`, left in dist_,
// came_from_ and came_by_. The nearest node of another group wins unless a preferred tip of another
// group lies within settings_.tip_preference more. Returns -1 when no other group is reachable.
int GroupBridges::nearest_target(std::size_t root) {
  const int nodes = static_cast<int>(adjacency_.size());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int k = 0; k < nodes; ++k)
    if (active_[k] && groups_.find(k) == root) {
      dist_[k] = 0.0;
      touched_.push_back(k);
      queue.push({0.0, k});
    }
  int target = -1, tip_target = -1;
  double target_dist = 0.0;
  while (!queue.empty()) {
    const auto [d, k] = queue.top();
    queue.pop();
    if (d > dist_[k]) continue;
    if (target >= 0 && d > target_dist + settings_.tip_preference) break;
    if (active_[k] && groups_.find(k) != root) {
      if (target < 0) {
        target = k;
        target_dist = d;
      }
      if (preferred_tip_[k]) {
        tip_target = k;
        break;
      }
      continue;  // other groups are targets, not ways through
    }
    for (const WorkingEdge& w : adjacency_[k]) {
      const double nd = d + w.length;
      if (nd > settings_.max_length || nd >= dist_[w.to]) continue;
      if (std::isinf(dist_[w.to])) touched_.push_back(w.to);
      dist_[w.to] = nd;
      came_from_[w.to] = k;
      came_by_[w.to] = w.voronoi_edge;
      queue.push({nd, w.to});
    }
  }
  if (tip_target >= 0) target = tip_target;
  return target;
}

// Appends the steps of the path nearest_target() found from group `root` to `target`, puts them on the
// group and merges it with the target's.
void GroupBridges::add_bridge(std::size_t root, int target, std::vector<BridgeLink>& links) {
  const int target_root = groups_.find(target);
  const bool to_old = has_old_[target_root];
  const bool to_tip = old_end_[target];
  for (int k = target; dist_[k] > 0.0; k = came_from_[k]) {
    links.push_back({came_from_[k], k, came_by_[k]});
    active_[k] = 1;
    groups_.unite(k, came_from_[k]);
  }
  const int merged = groups_.unite(root, target_root);
  has_old_[merged] = has_old_[merged] || to_old;
  if (to_old && to_tip)
    ++tip_bridges_;
  else
    ++branch_links_;
}

}  // namespace shellfrac::crack2d
