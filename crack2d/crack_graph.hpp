#pragma once
// The crack in one patch's parameter plane: a planar graph of straight segments (thesis sec. 4.4.2).
// Junctions (degree >= 3) are allowed so that branching and merging cracks are one graph.
// Append-only: vertices and edges are never removed or moved, so the edges added since a caller last
// looked are exactly [k, num_edges()); consumers rebuild only what those edges touch.
#include "crack2d/geometry.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_set>
#include <vector>

namespace shellfrac::crack2d {

class CrackGraph {
 public:
  int add_vertex(const Point& p);
  void add_edge(int a, int b);  // ignores a == b and duplicate edges (either orientation)

  const std::vector<Point>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 2>>& edges() const { return edges_; }
  size_t num_vertices() const { return vertices_.size(); }
  size_t num_edges() const { return edges_.size(); }
  bool empty() const { return edges_.empty(); }
  Segment segment(size_t e) const { return {vertices_[edges_[e][0]], vertices_[edges_[e][1]]}; }

  bool has_edge(int a, int b) const;
  // Edges incident to vertex v, in insertion order.
  const std::vector<int>& incident_edges(int v) const { return incident_[v]; }
  int degree(int v) const { return static_cast<int>(incident_[v].size()); }
  int other_end(int edge, int v) const { return edges_[edge][0] == v ? edges_[edge][1] : edges_[edge][0]; }
  // Connected components over vertices that have at least one edge; isolated vertices get -1.
  // Component ids are numbered in order of their smallest vertex index (deterministic).
  std::vector<int> component_labels(int* num_components = nullptr) const;

  // Strict-subset check: every vertex of `earlier` is here at the same index with bit-identical
  // coordinates, and every edge of `earlier` is an edge here.
  bool contains(const CrackGraph& earlier) const;

 private:
  static uint64_t edge_key(int a, int b);
  std::vector<Point> vertices_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::vector<int>> incident_;
  std::unordered_set<uint64_t> edge_keys_;
};

}  // namespace shellfrac::crack2d
