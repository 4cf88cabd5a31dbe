#include "crack2d/crack_graph.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shellfrac::crack2d {

uint64_t CrackGraph::edge_key(int a, int b) {
  const auto lo = static_cast<uint64_t>(static_cast<uint32_t>(std::min(a, b)));
  const auto hi = static_cast<uint64_t>(static_cast<uint32_t>(std::max(a, b)));
  return (lo << 32) | hi;
}

int CrackGraph::add_vertex(const Point& p) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
    throw std::invalid_argument("CrackGraph::add_vertex: non-finite coordinate for vertex " +
                                std::to_string(vertices_.size()));
  vertices_.push_back(p);
  incident_.emplace_back();
  return static_cast<int>(vertices_.size()) - 1;
}

void CrackGraph::add_edge(int a, int b) {
  const int n = static_cast<int>(vertices_.size());
  if (a < 0 || b < 0 || a >= n || b >= n)
    throw std::out_of_range("CrackGraph::add_edge: vertex index out of range (" + std::to_string(a) + ", " +
                            std::to_string(b) + "), graph has " + std::to_string(n) + " vertices");
  if (a == b || !edge_keys_.insert(edge_key(a, b)).second) return;
  incident_[a].push_back(static_cast<int>(edges_.size()));
  incident_[b].push_back(static_cast<int>(edges_.size()));
  edges_.push_back({a, b});
}

bool CrackGraph::has_edge(int a, int b) const { return edge_keys_.count(edge_key(a, b)) != 0; }

std::vector<int> CrackGraph::component_labels(int* num_components) const {
  std::vector<int> label(vertices_.size(), -1);
  int count = 0;
  std::vector<int> stack;
  for (size_t s = 0; s < vertices_.size(); ++s) {
    if (label[s] >= 0 || incident_[s].empty()) continue;
    label[s] = count;
    stack.assign(1, static_cast<int>(s));
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int e : incident_[v]) {
        const int w = other_end(e, v);
        if (label[w] < 0) {
          label[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  if (num_components) *num_components = count;
  return label;
}

bool CrackGraph::contains(const CrackGraph& earlier) const {
  if (earlier.vertices_.size() > vertices_.size()) return false;
  for (size_t i = 0; i < earlier.vertices_.size(); ++i) {
    // Bit-identical, not merely equal within a tolerance: consumers key caches on these coordinates.
    if (std::memcmp(earlier.vertices_[i].data(), vertices_[i].data(), 2 * sizeof(double)) != 0) return false;
  }
  for (const auto& e : earlier.edges_)
    if (!has_edge(e[0], e[1])) return false;
  return true;
}

}  // namespace shellfrac::crack2d
