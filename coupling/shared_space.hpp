#pragma once
#include <Eigen/Core>
#include <vector>

#include "coupling/edge.hpp"

namespace shellfrac::coupling {

// Exact seam closure, an opt-in beyond thesis Eq. 4.29. When the two edges' knots are not nested, the
// follower's spline space cannot represent every leader edge curve, and the least-squares follower of
// Eq. 4.29 leaves a gap. Both spaces contain the splines on the knots they share (the knot intersection,
// minimum multiplicities); if the leader's coupled rows are kept in that shared space, Eq. 4.29 and
// Eq. 4.34 reproduce them exactly and the seam closes to roundoff. The price is resolution: along the
// seam the leader moves only as finely as the shared knots allow (100 vs 125 cells share 25 spans).
// The rows are put there by coupling::RowProjection (row_projection.hpp).
struct SharedSpace {
  std::vector<double> knots;  // shared knot vector in the leader's edge parameter
  Eigen::MatrixXd E1;         // n_lambda x n_shared: leader row 1 = E1 s (rational knot insertion)
  Eigen::MatrixXd E2;         // the same for row 2 with its own weights; empty for C0
};

// Builds the shared space of a leader and a follower edge (`reversed` as for the interface). The leader's
// row weights must be representable on the shared knots (always true for polynomial edges); otherwise a
// CouplingError names the measured residual. Edges sharing no interior knot get a single polynomial
// piece (one span), which is valid but coarse.
SharedSpace shared_space(const Edge& leader, const Edge& follower, bool reversed, bool with_row2);

}  // namespace shellfrac::coupling
