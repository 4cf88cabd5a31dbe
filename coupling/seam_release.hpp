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
//
// C1 also ties each follower row-2 point to its row-1 partner and to the leader's cross-seam tangents
// c_lambda1,j - c_lambda2,j. A crack that runs between a row-1 point and its row-2 partner (obliquely
// through the first cell, or along the seam) tears that tangent: it then spans two fragments, and the
// follower's row 2 placed from it is dragged along by the opening crack (the spike of the three-patch
// L-sheet, docs/coupling.md). Torn leader tangents are dropped from the M1 rows like cut entries (sum
// and first moment kept on the nearest intact ones); a follower row-2 point whose own tangent is torn,
// or that has fewer than two intact tangents on its side, is released alone (its row-1 partner stays
// coupled).
struct SeamCut {
  Interface coupling;                   // the interface with the cut operators
  std::vector<unsigned char> released;  // per follower row entry (row 1, then row 2 for C1)
};

// Which cross-seam tangents (row 1 to row 2 of the same edge index) a crack separates; C1 only. Empty
// vectors mean none is torn.
struct TornTangents {
  std::vector<unsigned char> leader;    // per leader edge index
  std::vector<unsigned char> follower;  // per follower edge index
  bool any() const;
};

SeamCut cut_interface(const Interface& itf, const std::vector<double>& follower_along,
                      const std::vector<double>& leader_along, const std::vector<double>& seam_cracks,
                      const TornTangents& torn = {});

// The same for an exactly closed seam (itf.exact): the cracks split the seam into segments, and the
// leader's rows are kept in the shared space segment by segment (shared.E1/E2 of the result are block
// matrices, one block of shared coefficients per segment, rows of other segments zero), so each
// fragment's edge moves on its own. A follower point whose exact row (the follower's representation of
// the shared spline, M0 E, Eq. 4.29) only needs shared coefficients its own segment's leader points
// determine takes that row, written on the leader points through the segment's left inverse: away from
// the crack the follower's edge is the leader's to round-off. The points next to the crack take the
// least-squares cut rows of cut_interface. Leader row-2 points whose tangent is torn belong to no
// segment (zero row in E2): the caller keeps them where the grid puts them.
SeamCut cut_exact_interface(const Interface& itf, const std::vector<double>& follower_along,
                            const std::vector<double>& leader_along, const std::vector<double>& seam_cracks,
                            const TornTangents& torn = {});

}  // namespace shellfrac::coupling
