#pragma once
#include <Eigen/Core>
#include <vector>

#include "nurbs/knot_vector.hpp"

namespace shellfrac::coupling {

// Affine map from one edge parameter range onto another; `reversed` flips the direction, so that
// from_begin maps to to_end. Used to express the leader's edge knots in the follower's parameter.
struct ParameterMap {
  double from_begin, from_end, to_begin, to_end;
  bool reversed;

  double operator()(double t) const;
  double inverse(double s) const;
};

// Knots of `kv` mapped through `map`, sorted increasingly (a reversed map reverses their order). The
// end knots are set exactly to to_begin / to_end.
std::vector<double> map_knots(const nurbs::KnotVector& kv, const ParameterMap& map);

// Union with multiplicities of two sorted knot lists (thesis Eq. 4.27: k' = k_eta U k_lambda): each
// distinct value appears max(m_a, m_b) times. Values closer than `tolerance` are the same knot and take
// a's value, so that mapping roundoff (e.g. 1 - 0.7 != 0.3) never creates a sliver span.
std::vector<double> knot_union(const std::vector<double>& a, const std::vector<double>& b, double tolerance);

// Intersection with multiplicities of two sorted knot lists: each value present in both appears
// min(m_a, m_b) times (a's value). The spline space on these knots is the intersection of the two
// spaces: the curves both edges can represent exactly (used by exact seam closure).
std::vector<double> knot_intersection(const std::vector<double>& a, const std::vector<double>& b, double tolerance);

// The multiset difference refined \ original (with the same tolerance): the knots to insert into
// `original` to reach `refined`.
std::vector<double> knot_difference(const std::vector<double>& refined, const std::vector<double>& original,
                                    double tolerance);

// Virtual refinement of a follower (eta) and a leader (lambda) edge to their common knot vector
// (thesis Eq. 4.27-4.28, appendix D). Everything is expressed in the follower's edge parameter and
// order; the leader's rows are permuted when the edges run in opposite directions.
struct VirtualRefinement {
  nurbs::KnotVector common_knots;        // k' in the follower's parameter
  std::vector<double> common_weights;    // refined weights of the follower (the leader's agree up to scale)
  std::vector<double> follower_inserts;  // k' \ k_eta, follower parameter
  std::vector<double> leader_inserts;    // k' \ k_lambda, leader parameter
  Eigen::MatrixXd U_follower;            // n' x n_eta : refined points = U_eta c_eta (Eq. 4.28, D.8)
  Eigen::MatrixXd U_leader;              // n' x n_lambda: refined points = U_lambda c_lambda, follower order
  ParameterMap leader_to_follower;
};

// Builds the refinement. Degrees must agree (CouplingError otherwise); after refinement the two sets of
// weights must be proportional, i.e. the edges carry the same rational parameterisation.
VirtualRefinement virtual_refinement(const nurbs::KnotVector& follower_knots,
                                     const std::vector<double>& follower_weights,
                                     const nurbs::KnotVector& leader_knots,
                                     const std::vector<double>& leader_weights, bool reversed);

// Refined weights of an edge row (A w, appendix D), in the follower's order: used for weight ratios of
// row 2 to row 1 in the C1 constants.
std::vector<double> refined_row_weights(const nurbs::KnotVector& knots, const std::vector<double>& weights,
                                        const std::vector<double>& inserts, bool reverse_order);

}  // namespace shellfrac::coupling
