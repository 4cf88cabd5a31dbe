#pragma once
#include <Eigen/QR>
#include <Eigen/Core>

#include "coupling/interface.hpp"

namespace shellfrac::coupling {

// The coupled rows' state nearest, in the mass norm, to what the grid gave both patches, among the states
// the coupling allows. Unknowns s give the leader's coupled rows L = E s (E the identity, or the shared
// space of exact closure) and the follower's F = B L (B: Eq. 4.29 for row 1, Eq. 4.34 for row 2). Given
// the grid's L^ and F^ (positions or velocities), s minimises
//   |E s - L^|^2_{M_l} + |B E s - F^|^2_{M_f},
// i.e. (E^T M_l E + (BE)^T M_f BE) s = E^T M_l L^ + (BE)^T M_f F^. Every row of B sums to one, so constants
// pass through and the result keeps sum m L + sum m F: the rows' momentum (or centre of mass) is what
// the grid gave, where thesis sec. 4.8.1 drops the follower's share and takes the leader's alone
// (follower masses zero here). Rows are stacked row 1 then row 2 (C1), in each patch's edge order.
class RowProjection {
 public:
  // `exact`: the leader's rows live in itf.shared (exact closure). Masses per stacked row point: leader
  // masses positive, follower masses >= 0 (zero for rows a crack released or to ignore the follower).
  RowProjection(const Interface& itf, bool exact, const Eigen::VectorXd& leader_mass,
                const Eigen::VectorXd& follower_mass);

  // New leader rows from the grid's leader rows and follower rows (n_l x 3 and n_f x 3, stacked).
  PointRows apply(const PointRows& leader, const PointRows& follower) const;

  Eigen::Index leader_rows() const { return E_.rows(); }
  Eigen::Index follower_rows() const { return BE_.rows(); }

 private:
  Eigen::MatrixXd E_, BE_;
  Eigen::VectorXd leader_mass_, follower_mass_;
  // Rank-revealing: the segmented shared space of a cut exact seam can leave coefficients that no
  // leader point sees; the minimum-norm solution gives the same rows E s.
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> normal_;
};

// B of the class comment: the follower's stacked rows from the leader's stacked rows,
// [M0 0; M0 + M1, -M1] for C1 (c_eta2 = M0 c_l1 + M1 (c_l1 - c_l2)), M0 for C0.
Eigen::MatrixXd stacked_operator(const Interface& itf);

}  // namespace shellfrac::coupling
