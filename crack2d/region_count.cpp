#include "crack2d/region_count.hpp"

#include "core/union_find.hpp"

#include <stdexcept>
#include <string>

namespace shellfrac::crack2d {

using core::UnionFind;

int RegionCount::regions_with_at_least(size_t min_probes) const {
  int count = 0;
  for (size_t s : size) count += s >= min_probes ? 1 : 0;
  return count;
}

RegionCount count_regions(const CrackIndex& index, const Box& domain, int nu, int nv) {
  if (nu < 1 || nv < 1)
    throw std::invalid_argument("count_regions: probe grid must be at least 1 x 1, got " + std::to_string(nu) +
                                " x " + std::to_string(nv));
  RegionCount out;
  out.nu = nu;
  out.nv = nv;
  const Point extent = domain.hi - domain.lo;
  auto probe = [&](int i, int j) {
    return Point(domain.lo.x() + (i + 0.5) * extent.x() / nu, domain.lo.y() + (j + 0.5) * extent.y() / nv);
  };
  const size_t n = static_cast<size_t>(nu) * nv;
  UnionFind sets(n);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int k = j * nu + i;
      if (i + 1 < nu && !index.crosses(probe(i, j), probe(i + 1, j))) sets.unite(k, k + 1);
      if (j + 1 < nv && !index.crosses(probe(i, j), probe(i, j + 1))) sets.unite(k, k + nu);
    }
  out.label.assign(n, -1);
  std::vector<int> id_of_root(n, -1);
  for (size_t k = 0; k < n; ++k) {
    const int root = sets.find(static_cast<int>(k));
    if (id_of_root[root] < 0) {
      id_of_root[root] = out.regions++;
      out.size.push_back(0);
    }
    out.label[k] = id_of_root[root];
    ++out.size[out.label[k]];
  }
  return out;
}

std::vector<int> touching_components(const CrackGraph& graph, const CrackIndex& index, double tol,
                                     int* num_components) {
  const size_t n = graph.num_vertices();
  UnionFind sets(n);
  for (const auto& e : graph.edges()) sets.unite(e[0], e[1]);
  for (size_t v = 0; v < n; ++v) {
    const int vi = static_cast<int>(v);
    if (graph.degree(vi) == 0) continue;
    const Point& p = graph.vertices()[v];
    for (const uint32_t id : index.segments_near({p - Point::Constant(tol), p + Point::Constant(tol)})) {
      if (id >= graph.num_edges()) continue;
      const auto& e = graph.edges()[id];
      if (point_segment_distance(p, graph.segment(id)) <= tol) sets.unite(vi, e[0]);
    }
  }
  std::vector<int> label(n, -1), id_of_root(n, -1);
  int count = 0;
  for (size_t v = 0; v < n; ++v) {
    if (graph.degree(static_cast<int>(v)) == 0) continue;
    const int root = sets.find(static_cast<int>(v));
    if (id_of_root[root] < 0) id_of_root[root] = count++;
    label[v] = id_of_root[root];
  }
  if (num_components) *num_components = count;
  return label;
}

}  // namespace shellfrac::crack2d
