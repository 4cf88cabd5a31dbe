#pragma once
// Voronoi diagram of crack seeds (thesis sec. 4.4.2, Fig. 4.7b) computed by Boost.Polygon and returned
// as a planar graph of straight edges clipped to the patch domain. Each edge remembers the two seeds
// whose cells it separates, which is what the medial-axis selection and the consistency bookkeeping
// (historical seed pairs) key on.
//
// Quantisation: Boost.Polygon's Voronoi builder is exact for integer sites, so seed coordinates are
// mapped to a 2^28-step integer lattice spanning the larger side of the domain (about 3.7e-9 of the
// domain for a unit patch). The lattice origin sits off the domain centre by unequal fractions of a step
// (0.32 in u, 0.62 in v), so seeds placed symmetrically about the centre or a diagonal do not stay exactly
// symmetric: no bisector runs exactly through the sample points on such a symmetry line. Seeds closer
// than one lattice step collapse into one site (the lowest seed index wins). Output vertices are
// converted back to parameter coordinates in double precision, and vertices closer than
// kNodeMergeFraction (1e-7) of the domain are merged (grid-like seed sets are nearly cocircular and
// would otherwise yield edges a few lattice steps long).
#include "crack2d/geometry.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace shellfrac::crack2d {

struct SeedLattice {
  explicit SeedLattice(const Box& domain);
  std::array<int32_t, 2> quantise(const Point& p) const;
  Point to_parameter(double qx, double qy) const;
  static uint64_t key(const std::array<int32_t, 2>& q) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(q[0])) << 32) | static_cast<uint32_t>(q[1]);
  }
  Point centre;
  double scale;  // lattice steps per parameter unit
};

struct VoronoiGraph {
  struct Edge {
    int node_a, node_b;  // indices into nodes
    int seed_a, seed_b;  // seeds whose cells share this edge (seed_a < seed_b)
  };
  std::vector<Point> nodes;
  std::vector<Edge> edges;  // finite edges and rays, clipped to the domain; zero-length edges dropped
};

// Never throws on degenerate input: 0 or 1 distinct seed gives no edges, collinear seeds give the
// parallel bisector lines (clipped), duplicates are merged.
VoronoiGraph build_voronoi_graph(const std::vector<Point>& seeds, const Box& domain);

}  // namespace shellfrac::crack2d
