#pragma once
#include <Eigen/Core>

#include "coupling/edge.hpp"
#include "coupling/virtual_refinement.hpp"

namespace shellfrac::coupling {

// Rows of control points as an n x 3 matrix, so that operators act as M * X.
using PointRows = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// Moore-Penrose pseudo-inverse through Eigen's CompleteOrthogonalDecomposition (rank-revealing, so
// it stays defined if U ever loses rank). Computed once per interface at set-up.
Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& U);

// C0 operator of thesis Eq. 4.29: c_eta1 = M0 c_lambda1 with M0 = U_eta^+ U_lambda (n_eta x n_lambda).
inline Eigen::MatrixXd c0_operator(const Eigen::MatrixXd& U_follower_pinv, const Eigen::MatrixXd& U_leader) {
  return U_follower_pinv * U_leader;
}

// C1 operator (thesis Eq. 4.33-4.34, sign as derived in docs/coupling.md):
//   c_eta2 = M0 c_lambda1 + M1 (c_lambda1 - c_lambda2),  M1 = U_eta^+ D U_lambda.
inline Eigen::MatrixXd c1_operator(const Eigen::MatrixXd& U_follower_pinv, const Eigen::VectorXd& D,
                                   const Eigen::MatrixXd& U_leader) {
  return U_follower_pinv * D.asDiagonal() * U_leader;
}

// Mesh-dependent constants D (one per refined control point) from the cross-boundary knot spans:
//   D_k = (q_lambda h_eta gamma_lambda,k) / (q_eta h_lambda gamma_eta,k),
// q the cross degree, h the cross knot span touching the edge, gamma the refined weight ratio of row 2
// to row 1 (1 for polynomial patches). Exact when gamma is constant along each edge.
Eigen::VectorXd cross_scale_from_knots(const Edge& follower, const Edge& leader, const VirtualRefinement& r);

// Alternative D measured in the reference configuration: the ratio of the lengths of the refined
// inward row differences, |U_eta (c_eta2 - c_eta1)|_k / |U_lambda (c_lambda2 - c_lambda1)|_k. It makes
// the reference state a fixed point of the C1 operator even when the two patches map parameter to
// length with different scales.
Eigen::VectorXd cross_scale_from_reference(const VirtualRefinement& r, const PointRows& follower_diff,
                                           const PointRows& leader_diff);

}  // namespace shellfrac::coupling
