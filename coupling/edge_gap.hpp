#pragma once
#include <vector>

#include "coupling/edge.hpp"

namespace shellfrac::coupling {

// Maximum distance between the boundary curves of side sa of a and side sb of b (reference
// configuration). Points are paired by ARC-LENGTH FRACTION: the point at fraction f of the length of a
// is compared with the point at fraction f of b (1 - f when `reversed`, i.e. when b's edge parameter
// runs against a's). This is independent of how each edge is parameterised, is sensitive to a wrong
// orientation flag, and for two equal curves offset by a rigid translation returns exactly its length.
// `samples` (>= 2) points, uniform in each edge's own parameter, are taken on a and on b.
double edge_gap(const nurbs::NurbsSurface& a, Side sa, const nurbs::NurbsSurface& b, Side sb, bool reversed,
                int samples = 200);

// One pair of coincident edges found by detect_coincident_edges.
struct EdgeMatch {
  int patch_a;
  Side side_a;
  int patch_b;
  Side side_b;
  bool reversed;
  double gap;
};

// All pairs of edges of different patches whose end points match (either orientation) and whose
// edge_gap is <= tolerance, with patch_a < patch_b. Edges shorter than the tolerance (collapsed
// edges such as a cone apex) are skipped.
std::vector<EdgeMatch> detect_coincident_edges(const std::vector<nurbs::NurbsSurface>& patches, double tolerance,
                                               int samples = 64);

}  // namespace shellfrac::coupling
