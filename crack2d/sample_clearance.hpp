#pragma once
// Keeps new crack segments off the sample points. A sample lying exactly on a crack segment sees no
// control point on either side (visibility counts touching as blocked), so its material would lose its
// basis. Symmetric damage makes this common: the bisector of mirror-image seeds runs exactly along the
// symmetry line, through the quadrature points on it. The remedy is a shift of the free end of such a
// segment across the line by a tiny fixed amount (far below the sample spacing, far above round-off),
// which puts each of those samples on one definite side.
#include "crack2d/sample_grid.hpp"

#include <array>
#include <vector>

namespace shellfrac::crack2d {

// True when a sample point lies exactly on the closed segment ab (exact orientation test).
bool segment_hits_sample(const Point& a, const Point& b, const std::vector<Point>& samples, const SampleGrid& grid);

// nodes: positions of the ends of `edges`, shifted in place where needed; movable[k]: node k may be
// moved (a new vertex, not an existing crack vertex or a point on the patch edge). shift: the distance
// moved. Deterministic: edges in order, a fixed direction per edge.
void clear_samples_off_edges(std::vector<Point>& nodes, const std::vector<std::array<int, 2>>& edges,
                             const std::vector<char>& movable, const std::vector<Point>& samples,
                             const SampleGrid& grid, double shift);

}  // namespace shellfrac::crack2d
