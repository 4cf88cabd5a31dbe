// Virtual knot refinement (thesis Eq. 4.27-4.28, appendix D): knot unions with multiplicities,
// orientation and parameter ranges, and refinement matrices that leave the edge curve unchanged.
#include "coupling/virtual_refinement.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "coupling/coupling_operators.hpp"
#include "nurbs/knot_insertion.hpp"
#include "tests/coupling/coupling_test_helpers.hpp"

namespace shellfrac::coupling {
namespace {

using test::kPi;
using test::parametric_gap;

// The curve obtained from `original` by the refinement: knots k', weights w', points U c.
nurbs::NurbsCurve refined_curve(const VirtualRefinement& r, const Eigen::MatrixXd& U, const nurbs::NurbsCurve& original,
                                const std::vector<double>& weights) {
  PointRows c(static_cast<Eigen::Index>(original.control_points().size()), 3);
  for (std::size_t i = 0; i < original.control_points().size(); ++i) {
    c.row(static_cast<Eigen::Index>(i)) = original.control_points()[i].transpose();
  }
  const PointRows q = U * c;
  nurbs::Vec3List pts;
  for (Eigen::Index k = 0; k < q.rows(); ++k) pts.push_back(q.row(k).transpose());
  return nurbs::NurbsCurve(r.common_knots, std::move(pts), weights);
}

// The same curve with its parameter running backwards.
nurbs::NurbsCurve reversed_curve(const nurbs::NurbsCurve& c) {
  std::vector<double> knots;
  const double lo = c.knots().domain_begin(), hi = c.knots().domain_end();
  for (auto it = c.knots().knots().rbegin(); it != c.knots().knots().rend(); ++it) knots.push_back(lo + hi - *it);
  nurbs::Vec3List pts(c.control_points().rbegin(), c.control_points().rend());
  std::vector<double> w(c.weights().rbegin(), c.weights().rend());
  return nurbs::NurbsCurve(nurbs::KnotVector(std::move(knots), c.degree()), std::move(pts), std::move(w));
}

// Weights of the leader refined in follower order (the refinement stores only the follower's).
std::vector<double> leader_weights(const VirtualRefinement& r, const nurbs::NurbsCurve& leader) {
  return refined_row_weights(leader.knots(), leader.weights(), r.leader_inserts, r.leader_to_follower.reversed);
}

TEST(KnotUnion, MaxMultiplicityOfSharedKnots) {
  const std::vector<double> a = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
  const std::vector<double> b = {0, 0, 0, 0.25, 0.5, 0.75, 0.75, 1, 1, 1};
  EXPECT_EQ(knot_union(a, b, 1e-12), (std::vector<double>{0, 0, 0, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1}));
  EXPECT_EQ(knot_difference(knot_union(a, b, 1e-12), a, 1e-12), (std::vector<double>{0.25, 0.75, 0.75}));
  EXPECT_EQ(knot_difference(knot_union(a, b, 1e-12), b, 1e-12), (std::vector<double>{0.5}));
}

TEST(KnotUnion, RoundoffCloseKnotsMergeToTheFirstVector) {
  // 1 - 0.7 is 0.30000000000000004: it must not add a sliver span next to 0.3.
  const std::vector<double> a = {0, 0, 0, 0.3, 1, 1, 1};
  const std::vector<double> b = {0, 0, 0, 1.0 - 0.7, 1, 1, 1};
  ASSERT_NE(a[3], b[3]);
  EXPECT_EQ(knot_union(a, b, 1e-10), a);
}

TEST(VirtualRefinement, ReversedLeaderOnAnotherParameterRange) {
  // Follower on [2, 6], leader on [0, 1] running backwards: leader t maps to 6 - 4 t.
  const nurbs::KnotVector follower({2, 2, 2, 3, 4, 4, 6, 6, 6}, 2);
  const nurbs::KnotVector leader({0, 0, 0, 0.25, 0.25, 0.6, 1, 1, 1}, 2);
  const VirtualRefinement r =
      virtual_refinement(follower, std::vector<double>(6, 1.0), leader, std::vector<double>(6, 1.0), true);
  // 0.25 (x2) -> 5 (x2), 0.6 -> 3.6.
  const std::vector<double> expected = {2, 2, 2, 3, 3.6, 4, 4, 5, 5, 6, 6, 6};
  ASSERT_EQ(r.common_knots.size(), static_cast<int>(expected.size()));
  for (int i = 0; i < r.common_knots.size(); ++i) EXPECT_NEAR(r.common_knots[i], expected[static_cast<std::size_t>(i)], 1e-14);
  EXPECT_EQ(r.common_knots.multiplicity(5.0), 2);
  std::vector<double> fi = r.follower_inserts, li = r.leader_inserts;
  std::sort(fi.begin(), fi.end());
  std::sort(li.begin(), li.end());
  ASSERT_EQ(fi.size(), 3u);
  EXPECT_NEAR(fi[0], 3.6, 1e-14);
  EXPECT_EQ(fi[1], 5.0);
  EXPECT_EQ(fi[2], 5.0);
  // Follower-only knots 3 and 4 (x2) in the leader parameter: 0.75 and 0.5 (x2).
  EXPECT_EQ(li, (std::vector<double>{0.5, 0.5, 0.75}));
  EXPECT_EQ(r.U_follower.rows(), 9);
  EXPECT_EQ(r.U_leader.rows(), 9);
}

TEST(VirtualRefinement, PolynomialEdgeUnchangedBothSidesAndOrientations) {
  const nurbs::KnotVector kf({0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1}, 3);
  const nurbs::NurbsCurve follower(kf,
                                   {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 0.5, 2), Vec3(4, 3, -1),
                                    Vec3(5, 0, 0), Vec3(6, 1, 1)},
                                   std::vector<double>(7, 1.0));
  const nurbs::NurbsCurve leader_fwd(nurbs::KnotVector({-1, -1, -1, -1, 0, 1, 1, 1, 1}, 3),
                                     {Vec3(0, 1, 0), Vec3(2, 0, 1), Vec3(1, 1, 2), Vec3(3, 3, 0), Vec3(4, 0, 1)},
                                     std::vector<double>(5, 1.0));
  for (bool reversed : {false, true}) {
    const nurbs::NurbsCurve leader = reversed ? reversed_curve(leader_fwd) : leader_fwd;
    const VirtualRefinement r = virtual_refinement(kf, follower.weights(), leader.knots(), leader.weights(), reversed);
    EXPECT_EQ(r.common_knots.num_basis(), 7 + 1);  // one leader-only knot (0.5 in follower parameter)
    const double gap_f = parametric_gap(follower, refined_curve(r, r.U_follower, follower, r.common_weights), false);
    const double gap_l =
        parametric_gap(leader, refined_curve(r, r.U_leader, leader, leader_weights(r, leader)), reversed);
    EXPECT_LT(gap_f, 1e-12);
    EXPECT_LT(gap_l, 1e-12) << "reversed = " << reversed;
  }
}

TEST(VirtualRefinement, RationalQuarterCircleNonNestedKnots) {
  // The same quarter circle with interior knots {1/3, 2/3} (leader) and {1/4, 1/2, 3/4} (follower).
  const nurbs::NurbsCurve arc = nurbs::circular_arc(2.0, 0.0, 0.5 * kPi);
  const nurbs::NurbsCurve leader = nurbs::insert_knots(arc, {1.0 / 3, 2.0 / 3});
  const nurbs::NurbsCurve follower = nurbs::insert_knots(arc, {0.25, 0.5, 0.75});
  for (bool reversed : {false, true}) {
    const nurbs::NurbsCurve lead = reversed ? reversed_curve(leader) : leader;
    const VirtualRefinement r =
        virtual_refinement(follower.knots(), follower.weights(), lead.knots(), lead.weights(), reversed);
    EXPECT_EQ(r.common_knots.num_basis(), 3 + 5);
    const nurbs::NurbsCurve rf = refined_curve(r, r.U_follower, follower, r.common_weights);
    const nurbs::NurbsCurve rl = refined_curve(r, r.U_leader, lead, leader_weights(r, lead));
    EXPECT_LT(parametric_gap(follower, rf, false), 1e-12);
    EXPECT_LT(parametric_gap(lead, rl, reversed), 1e-12);
    // Both refine to the same control points (Eq. 4.28: U_eta c_eta = U_lambda c_lambda).
    double worst = 0;
    for (std::size_t k = 0; k < rf.control_points().size(); ++k) {
      worst = std::max(worst, (rf.control_points()[k] - rl.control_points()[k]).norm());
    }
    EXPECT_LT(worst, 1e-12);
    // Still on the circle of radius 2.
    for (int s = 0; s <= 200; ++s) EXPECT_NEAR(rl.point(s / 200.0).norm(), 2.0, 1e-12);
  }
}

TEST(VirtualRefinement, RationalCylinderEdge) {
  // Bottom circular edges (V0) of two cylinder segments with 4 and 6 circumferential cells.
  const nurbs::NurbsSurface coarse = nurbs::cylinder_segment(1.5, 1.0, 0.5 * kPi, 4, 3);
  const nurbs::NurbsSurface fine = nurbs::cylinder_segment(1.5, 1.0, 0.5 * kPi, 6, 2);
  const nurbs::NurbsCurve lead = edge_curve(coarse, Side::V0);
  const nurbs::NurbsCurve fol = edge_curve(fine, Side::V0);
  const VirtualRefinement r = virtual_refinement(fol.knots(), fol.weights(), lead.knots(), lead.weights(), false);
  EXPECT_EQ(r.common_knots.num_spans(), 8);  // {1/4,1/2,3/4} U {1/6,1/3,1/2,2/3,5/6}
  EXPECT_LT(parametric_gap(fol, refined_curve(r, r.U_follower, fol, r.common_weights), false), 1e-12);
  EXPECT_LT(parametric_gap(lead, refined_curve(r, r.U_leader, lead, leader_weights(r, lead)), false), 1e-12);
}

TEST(VirtualRefinement, RejectsDifferentDegreesAndIncompatibleWeights) {
  const nurbs::KnotVector k2 = nurbs::KnotVector::open_uniform(2, 3);
  const nurbs::KnotVector k3 = nurbs::KnotVector::open_uniform(3, 3);
  EXPECT_THAT(test::error_message([&] {
                virtual_refinement(k2, std::vector<double>(5, 1.0), k3, std::vector<double>(6, 1.0), false);
              }),
              ::testing::HasSubstr("edge degrees differ: follower degree 2, leader degree 3"));
  EXPECT_THAT(test::error_message([&] {
                virtual_refinement(k2, std::vector<double>(5, 1.0), k2, {1, 1, 0.5, 1, 1}, false);
              }),
              ::testing::HasSubstr("rational edges have incompatible weights"));
}

}  // namespace
}  // namespace shellfrac::coupling
