#pragma once
// Pieces of a patch cut by its crack graph, counted on a regular probe grid: the nu x nv cell centres
// of the parameter rectangle, each joined to its right and upper neighbour unless the segment between
// them touches the crack (CrackIndex::crosses, exact). A region narrower than the probe spacing may be
// missed or merged, so choose the grid finer than the smallest piece of interest.
#include "crack2d/crack_index.hpp"

#include <cstddef>
#include <vector>

namespace shellfrac::crack2d {

struct RegionCount {
  int regions = 0;               // connected pieces of the probe grid
  std::vector<int> label;        // per probe (row-major, u fastest): region id, numbered by first probe
  std::vector<size_t> size;      // probes per region
  int nu = 0, nv = 0;
  // Regions holding at least min_probes probes (e.g. one simulation cell's worth).
  int regions_with_at_least(size_t min_probes) const;
};

RegionCount count_regions(const CrackIndex& index, const Box& domain, int nu, int nv);

// Connected parts of the crack as a point set: like CrackGraph::component_labels, but a vertex lying
// on another segment (within tol, e.g. the end of a join that landed inside a segment) connects to it.
// Labels per vertex (-1 for vertices without edges), numbered in order of their smallest vertex.
std::vector<int> touching_components(const CrackGraph& graph, const CrackIndex& index, double tol,
                                     int* num_components = nullptr);

}  // namespace shellfrac::crack2d
