#pragma once
#include <Eigen/Core>
#include <vector>

#include "coupling/interface.hpp"

namespace shellfrac::coupling {

// Where a point of a coupled patch sits relative to the seam, in the seam's own chart: `along` in [0, 1]
// runs with the leader's edge parameter (the follower's is flipped when the edges are reversed), and
// `across` is the parameter distance from the edge into the patch, in units of the patch's cross
// parameter range.
struct SeamCoordinate {
  double along = 0;
  double across = 0;
};

// Seam coordinate of surface parameter uv of `surface`, seen from the interface side `side`; `flip`
// says this patch's edge runs against the seam's direction (follower of a reversed interface).
SeamCoordinate seam_coordinate(const nurbs::NurbsSurface& surface, Side side, bool flip, const Eigen::Vector2d& uv);
// The surface parameter of the edge point at seam coordinate `along` (inverse of the above at across = 0).
Eigen::Vector2d seam_edge_parameter(const nurbs::NurbsSurface& surface, Side side, bool flip, double along);
// Converts a direction in the seam chart (d.x along, d.y across, inward) to the patch's parameter plane.
Eigen::Vector2d seam_direction_to_parameter(const nurbs::NurbsSurface& surface, Side side, bool flip,
                                            const Eigen::Vector2d& d);
Eigen::Vector2d parameter_direction_to_seam(const nurbs::NurbsSurface& surface, Side side, bool flip,
                                            const Eigen::Vector2d& d);

// The coupling after cracks have crossed the seam. Follower edge point k (seam coordinate
// follower_along[k], row 1 order) is set from the leader edge points j (leader_along[j]) through row k
// of M0, and for C1 its row-2 partner also through M1. A crack meeting the seam at c strictly between k
// and j cuts that connection (thesis sec. 4.8 with sec. 4.4: fragments must be able to leave): the entry
// is dropped, and the two nearest same-side entries are corrected so that the row still reproduces
// fields affine along the seam (sum and first moment kept: rest geometry of straight edges and rigid
// motions of the fragment are carried exactly). A point with fewer than two same-side leader points
// left is released: it then moves with its own patch only.
struct SeamCut {
  Interface coupling;                   // the interface with the cut operators
  std::vector<unsigned char> released;  // per follower row entry (row 1, then row 2 for C1)
};
SeamCut cut_interface(const Interface& itf, const std::vector<double>& follower_along,
                      const std::vector<double>& leader_along, const std::vector<double>& seam_cracks);

}  // namespace shellfrac::coupling
