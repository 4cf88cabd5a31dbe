#pragma once
// Prescribed cuts (user-drawn slits, holes) in a patch's parameter plane. They enter the crack graph as
// permanent historical lines, so consistent extraction builds around them like any earlier crack.
#include "crack2d/crack_graph.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace shellfrac::crack2d {

class CutError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws CutError naming the problem and the offending vertex/segment index: too few points (2 for an
// open polyline, 3 for a closed curve), a non-finite or out-of-domain vertex, a zero-length segment, or
// two segments that intersect other than at their shared vertex (exact predicates).
void validate_cut(const std::vector<Point>& polyline, bool closed, const Box& domain);

// Validates, then appends the cut to g as new vertices and edges (a closed curve gets its closing edge).
// Returns the index of the first vertex added.
int append_cut(CrackGraph& g, const std::vector<Point>& polyline, bool closed, const Box& domain);

}  // namespace shellfrac::crack2d
