#include "coupling/shared_space.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <string>

#include "coupling/coupling_error.hpp"
#include "coupling/format.hpp"
#include "coupling/virtual_refinement.hpp"
#include "nurbs/knot_insertion.hpp"

namespace shellfrac::coupling {

namespace {

// Knots closer than this fraction of the parameter range are the same knot (as in virtual_refinement).
constexpr double kKnotTolerance = 1e-10;
// Allowed relative residual of the leader's weights on the shared knots.
constexpr double kWeightTolerance = 1e-10;

// Rational knot insertion from the shared knots onto the leader's: leader points = E s. The shared
// weights are the least-squares solution of A w_s = w_lambda (A the homogeneous insertion), which must be
// exact for the same rational curve to live in both spaces.
Eigen::MatrixXd insertion_from_shared(const nurbs::KnotVector& shared, const std::vector<double>& inserts,
                                      const std::vector<double>& leader_weights, const char* row) {
  const std::vector<double> ones(static_cast<std::size_t>(shared.num_basis()), 1.0);
  const Eigen::MatrixXd A(nurbs::refine_knots(shared, ones, inserts).A);
  const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(leader_weights.data(),
                                                              static_cast<Eigen::Index>(leader_weights.size()));
  const Eigen::VectorXd ws = A.completeOrthogonalDecomposition().solve(w);
  const double residual = (A * ws - w).cwiseAbs().maxCoeff();
  if (residual > kWeightTolerance * w.cwiseAbs().maxCoeff()) {
    throw CouplingError(std::string("exact closure: the leader's ") + row + " weights are not representable on the " +
                        std::to_string(shared.num_spans()) + " knot spans both edges share (residual " +
                        format_number(residual) + "); use \"closure\": \"least_squares\" for this seam");
  }
  const std::vector<double> ws_list(ws.data(), ws.data() + ws.size());
  return Eigen::MatrixXd(nurbs::refine_knots(shared, ws_list, inserts).U);
}

}  // namespace

SharedSpace shared_space(const Edge& leader, const Edge& follower, bool reversed, bool with_row2) {
  const nurbs::KnotVector& kl = leader.knots;
  const nurbs::KnotVector& kf = follower.knots;
  if (kl.degree() != kf.degree()) {
    throw CouplingError("exact closure: the edge degrees differ (" + std::to_string(kl.degree()) + " vs " +
                        std::to_string(kf.degree()) + ")");
  }
  const ParameterMap follower_to_leader{kf.domain_begin(), kf.domain_end(), kl.domain_begin(), kl.domain_end(),
                                        reversed};
  const double tol = kKnotTolerance * (kl.domain_end() - kl.domain_begin());
  SharedSpace s;
  s.knots = knot_intersection(kl.knots(), map_knots(kf, follower_to_leader), tol);
  const nurbs::KnotVector shared(s.knots, kl.degree());
  // The leader's knots missing from the shared ones, taken with the leader's own values so that the
  // inserted knot vector is the leader's exactly.
  const std::vector<double> inserts = knot_difference(kl.knots(), s.knots, tol);
  s.E1 = insertion_from_shared(shared, inserts, leader.weights1, "edge");
  if (with_row2) s.E2 = insertion_from_shared(shared, inserts, leader.weights2, "second-row");
  if (s.E1.rows() != static_cast<Eigen::Index>(leader.row1.size())) {  // guards the tolerances
    throw CouplingError("exact closure: the shared space maps onto " + std::to_string(s.E1.rows()) +
                        " points, the leader edge has " + std::to_string(leader.row1.size()));
  }
  return s;
}

}  // namespace shellfrac::coupling
