#pragma once
// Disjoint sets over dense indices 0..n-1 with path halving. The smaller root always wins a union, so
// the representative of a set is its smallest member whatever the order of the unions: labels derived
// from roots are deterministic (the crack extraction, phantom-node partition and fragment counts rely on it).
#include <cstddef>
#include <numeric>
#include <vector>

namespace shellfrac::core {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n = 0) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }

  std::size_t size() const { return parent_.size(); }
  // Appends a singleton set and returns its index.
  std::size_t add() {
    parent_.push_back(parent_.size());
    return parent_.size() - 1;
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  // Joins the sets of a and b; returns the representative (the smaller root).
  std::size_t unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return a;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return a;
  }
  bool same(std::size_t a, std::size_t b) { return find(a) == find(b); }
  // Number of sets (roots).
  std::size_t count_sets() {
    std::size_t n = 0;
    for (std::size_t k = 0; k < parent_.size(); ++k) n += find(k) == k ? 1 : 0;
    return n;
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace shellfrac::core
