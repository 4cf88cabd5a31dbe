#pragma once
// Disjoint sets with path halving. The smaller root wins every union, so labels never depend on the
// order in which unions are made (deterministic extraction).
#include <numeric>
#include <utility>
#include <vector>

namespace shellfrac::crack2d {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  int unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return a;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return a;
  }
  void grow(size_t n) {  // adds singleton sets up to size n
    for (size_t i = parent_.size(); i < n; ++i) parent_.push_back(static_cast<int>(i));
  }
  size_t size() const { return parent_.size(); }

 private:
  std::vector<int> parent_;
};

}  // namespace shellfrac::crack2d
