#include "coupling/coupling_operators.hpp"

#include <Eigen/QR>
#include <string>

#include "coupling/coupling_error.hpp"
#include "coupling/format.hpp"

namespace shellfrac::coupling {

Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& U) {
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(U);
  return cod.pseudoInverse();
}

Eigen::VectorXd cross_scale_from_knots(const Edge& follower, const Edge& leader, const VirtualRefinement& r) {
  const double base = (static_cast<double>(leader.cross_degree) * follower.cross_first_span) /
                      (static_cast<double>(follower.cross_degree) * leader.cross_first_span);
  const bool reversed = r.leader_to_follower.reversed;
  const std::vector<double> f1 = refined_row_weights(follower.knots, follower.weights1, r.follower_inserts, false);
  const std::vector<double> f2 = refined_row_weights(follower.knots, follower.weights2, r.follower_inserts, false);
  const std::vector<double> l1 = refined_row_weights(leader.knots, leader.weights1, r.leader_inserts, reversed);
  const std::vector<double> l2 = refined_row_weights(leader.knots, leader.weights2, r.leader_inserts, reversed);
  Eigen::VectorXd D(static_cast<Eigen::Index>(f1.size()));
  for (std::size_t k = 0; k < f1.size(); ++k) {
    const double gamma_follower = f2[k] / f1[k];
    const double gamma_leader = l2[k] / l1[k];
    D[static_cast<Eigen::Index>(k)] = base * gamma_leader / gamma_follower;
  }
  return D;
}

Eigen::VectorXd cross_scale_from_reference(const VirtualRefinement& r, const PointRows& follower_diff,
                                           const PointRows& leader_diff) {
  const PointRows rf = r.U_follower * follower_diff;
  const PointRows rl = r.U_leader * leader_diff;
  Eigen::VectorXd D(rf.rows());
  for (Eigen::Index k = 0; k < rf.rows(); ++k) {
    const double denom = rl.row(k).norm();
    if (!(denom > 0.0)) {
      throw CouplingError("cannot measure the C1 constant at refined control point " + std::to_string(k) +
                          ": the leader's rows 1 and 2 coincide there (length " + format_number(denom) + ")");
    }
    D[k] = rf.row(k).norm() / denom;
  }
  return D;
}

}  // namespace shellfrac::coupling
