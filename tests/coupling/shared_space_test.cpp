// Exact seam closure (coupling/shared_space.hpp): the spline space two non-nested edges share, the
// insertion matrices onto the leader and the checks that refuse it; and the mass-weighted projection of
// a seam's rows onto the coupling constraint (coupling/row_projection.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coupling/interface.hpp"
#include "coupling/row_projection.hpp"
#include "coupling/shared_space.hpp"
#include "coupling/virtual_refinement.hpp"
#include "nurbs/knot_insertion.hpp"
#include "tests/coupling/coupling_test_helpers.hpp"

namespace shellfrac::coupling {
namespace {

using test::frame_at;

InterfaceOptions exact(Continuity continuity) {
  InterfaceOptions o;
  o.continuity = continuity;
  o.closure = Closure::Exact;
  return o;
}

TEST(SharedSpace, KnotIntersectionKeepsCommonKnotsWithTheLowerMultiplicity) {
  const std::vector<double> a{0, 0, 0, 0.2, 0.4, 0.4, 0.6, 0.8, 1, 1, 1};
  const std::vector<double> b{0, 0, 0, 0.4, 0.5, 0.6 + 1e-13, 0.6 + 1e-13, 1, 1, 1};
  EXPECT_EQ(knot_intersection(a, b, 1e-10), (std::vector<double>{0, 0, 0, 0.4, 0.6, 1, 1, 1}));
}

TEST(SharedSpace, NonNestedFlatEdgesShareEveryCommonKnot) {
  // 8 vs 10 cells along the seam share the knot 0.5: two quadratic spans, four control points.
  const nurbs::NurbsSurface leader = nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 10);
  const Interface itf = make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false, exact(Continuity::C1));
  EXPECT_EQ(itf.shared.knots, (std::vector<double>{0, 0, 0, 0.5, 1, 1, 1}));
  ASSERT_EQ(itf.shared.E1.rows(), 10);
  ASSERT_EQ(itf.shared.E1.cols(), 4);
  // E1 is the knot insertion from the shared knots onto the leader's: a shared-space curve evaluated
  // through it is the same curve (independent check with nurbs::insert_knots).
  const nurbs::NurbsCurve coarse(nurbs::KnotVector(itf.shared.knots, 2),
                                 {Vec3(0, 0, 0.1), Vec3(0.2, 0.3, -0.4), Vec3(-0.1, 0.7, 0.5), Vec3(0.3, 1, 0)}, {1, 1, 1, 1});
  std::vector<double> inserts;
  for (int i = 1; i < 8; ++i)
    if (i != 4) inserts.push_back(i / 8.0);
  const nurbs::NurbsCurve fine = nurbs::insert_knots(coarse, inserts);
  PointRows s(4, 3);
  for (int k = 0; k < 4; ++k) s.row(k) = coarse.control_points()[static_cast<std::size_t>(k)];
  const PointRows mapped = itf.shared.E1 * s;
  for (int k = 0; k < 10; ++k) EXPECT_LT((mapped.row(k).transpose() - fine.control_points()[static_cast<std::size_t>(k)]).norm(), 1e-14);
}

// Stacked rows (row 1 then row 2 for C1) of a control point list.
PointRows gather(const nurbs::Vec3List& x, const std::vector<int>& row1, const std::vector<int>& row2 = {}) {
  PointRows out(static_cast<Eigen::Index>(row1.size() + row2.size()), 3);
  Eigen::Index k = 0;
  for (int i : row1) out.row(k++) = x[static_cast<std::size_t>(i)];
  for (int i : row2) out.row(k++) = x[static_cast<std::size_t>(i)];
  return out;
}

Eigen::VectorXd random_masses(std::mt19937& rng, Eigen::Index n) {
  std::uniform_real_distribution<double> mass(0.5, 2.0);
  Eigen::VectorXd m(n);
  for (Eigen::Index k = 0; k < n; ++k) m[k] = mass(rng);
  return m;
}

PointRows random_rows(std::mt19937& rng, Eigen::Index n) {
  PointRows v(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) v.row(k) = test::random_vec(rng, 1.0);
  return v;
}

TEST(RowProjection, LeaderOnlyExactClosureKeepsMomentumAndIsIdempotent) {
  const nurbs::NurbsSurface leader = nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 10);
  const Interface itf = make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false, exact(Continuity::C0));
  std::mt19937 rng(3);
  const Eigen::VectorXd m = random_masses(rng, 10);
  const RowProjection P(itf, true, m, Eigen::VectorXd::Zero(12));
  const PointRows none = PointRows::Zero(12, 3);
  const PointRows v = random_rows(rng, 10);
  const PointRows pv = P.apply(v, none);
  // Momentum sum_k m_k v_k is unchanged (to roundoff), projecting twice changes nothing, the result lies
  // in the shared space, and the residual is M-orthogonal to that space (the nearest state).
  EXPECT_LT((m.transpose() * pv - m.transpose() * v).norm(), 1e-13);
  EXPECT_GT((pv - v).norm(), 0.1);
  EXPECT_LT((P.apply(pv, none) - pv).cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::MatrixXd& E = itf.shared.E1;
  const PointRows s = E.completeOrthogonalDecomposition().solve(pv);
  EXPECT_LT((E * s - pv).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((E.transpose() * m.asDiagonal() * (v - pv)).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(RowProjection, BothSidesConformingSeamTakesTheMassWeightedMean) {
  // Conforming C0 (8 and 8 cells): the follower's edge is the leader's, so the nearest state puts every
  // shared point at the mass-weighted mean of the two grid values.
  const nurbs::NurbsSurface leader = nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 8);
  InterfaceOptions o;
  o.continuity = Continuity::C0;
  const Interface itf = make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false, o);
  std::mt19937 rng(11);
  const Eigen::VectorXd ml = random_masses(rng, 10), mf = random_masses(rng, 10);
  const PointRows l = random_rows(rng, 10), f = random_rows(rng, 10);
  const PointRows got = RowProjection(itf, false, ml, mf).apply(l, f);
  for (Eigen::Index k = 0; k < 10; ++k) {
    const Eigen::RowVector3d mean = (ml[k] * l.row(k) + mf[k] * f.row(k)) / (ml[k] + mf[k]);
    EXPECT_LT((got.row(k) - mean).norm(), 1e-14) << k;
  }
}

TEST(RowProjection, BothSidesNonNestedC1KeepsTheRowsMomentum) {
  // 8 vs 10 cells, C1, rows 1 and 2 of both sides: the result satisfies the coupling (the follower rows
  // are B L), keeps sum m L + sum m F of the grid's rows, and leaves a coupled state unchanged.
  const nurbs::NurbsSurface leader = nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 10);
  const Interface itf = make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false);
  ASSERT_EQ(itf.continuity, Continuity::C1);
  std::mt19937 rng(17);
  const Eigen::VectorXd ml = random_masses(rng, 20), mf = random_masses(rng, 24);
  const PointRows l = random_rows(rng, 20), f = random_rows(rng, 24);
  const RowProjection P(itf, false, ml, mf);
  const PointRows got = P.apply(l, f);
  const Eigen::MatrixXd B = stacked_operator(itf);
  const Eigen::RowVector3d before = ml.transpose() * l + mf.transpose() * f;
  const Eigen::RowVector3d after = ml.transpose() * got + mf.transpose() * (B * got);
  EXPECT_LT((after - before).norm(), 1e-12 * before.norm());
  // B reproduces Eq. 4.29 / 4.34 as the interface applies them.
  nurbs::Vec3List lx = leader.control_points(), fx = follower.control_points();
  for (std::size_t k = 0; k < 10; ++k) {
    lx[static_cast<std::size_t>(itf.leader_row1[k])] = got.row(static_cast<Eigen::Index>(k));
    lx[static_cast<std::size_t>(itf.leader_row2[k])] = got.row(static_cast<Eigen::Index>(10 + k));
  }
  itf.apply(lx, fx);
  EXPECT_LT((gather(fx, itf.follower_row1, itf.follower_row2) - B * got).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((P.apply(got, B * got) - got).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(SharedSpace, RationalArcEdgesCloseExactly) {
  // Two quarter-cylinder rings stacked along the axis, 4 vs 6 cells around the shared circular edge
  // (shared knot 0.5). The arc's weight function is one rational quadratic, so it lives on the shared
  // knots; random motion projected there is reproduced by the follower to roundoff.
  const nurbs::NurbsSurface lower = nurbs::cylinder_segment(1.0, 1.0, 0.5 * test::kPi, 4, 3);
  const nurbs::NurbsSurface upper = nurbs::cylinder_segment(1.0, 1.0, 0.5 * test::kPi, 6, 5, frame_at(Vec3(0, 1, 0)));
  const Interface itf = make_interface(lower, 0, Side::V1, upper, 1, Side::V0, false, exact(Continuity::C0));
  ASSERT_EQ(itf.shared.E1.cols(), 4);
  std::mt19937 rng(5);
  nurbs::Vec3List lx = lower.control_points(), fx = upper.control_points();
  PointRows x = gather(lx, itf.leader_row1);
  for (Eigen::Index k = 0; k < x.rows(); ++k) x.row(k) += test::random_vec(rng, 0.2).transpose();
  const auto n = static_cast<Eigen::Index>(itf.follower_row1.size());
  const PointRows px = RowProjection(itf, true, Eigen::VectorXd::Ones(x.rows()), Eigen::VectorXd::Zero(n))
                           .apply(x, PointRows::Zero(n, 3));
  for (std::size_t k = 0; k < itf.leader_row1.size(); ++k)
    lx[static_cast<std::size_t>(itf.leader_row1[k])] = px.row(static_cast<Eigen::Index>(k));
  itf.apply(lx, fx);
  const double gap = test::parametric_gap(edge_curve(test::with_points(lower, lx), Side::V1),
                                          edge_curve(test::with_points(upper, fx), Side::V0), false);
  EXPECT_LT(gap, 1e-12);
}

TEST(SharedSpace, WeightsTheSharedKnotsCannotCarryAreRefused) {
  // A leader edge of 4 spans whose weights bump in the middle, against a follower of 3 spans: they
  // share no interior knot, and no single rational quadratic has those weights.
  nurbs::NurbsSurface bumped = nurbs::flat_patch(1.0, 1.0, 2, 4);
  std::vector<double> w = bumped.weights();
  w[static_cast<std::size_t>(bumped.flat_index(3, 2))] = 2.0;  // the middle point of side U1 (i = 3)
  bumped = nurbs::NurbsSurface(bumped.knots_u(), bumped.knots_v(), bumped.control_points(), w);
  const Edge lead = extract_edge(bumped, Side::U1);
  const Edge follow = extract_edge(nurbs::flat_patch(1.0, 1.0, 2, 3), Side::U0);
  const std::string message = test::error_message([&] { shared_space(lead, follow, false, false); });
  EXPECT_NE(message.find("not representable on the 1 knot spans"), std::string::npos) << message;
}

TEST(SharedSpace, ALeaderRowOutsideTheSharedSpaceIsRefused) {
  // The rest state must already be closed: a leader whose second row has a 1 cm bump cannot be held in
  // the 2-span shared space of 8 vs 10 cells without moving it.
  const nurbs::NurbsSurface flat = nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)));
  nurbs::Vec3List x = flat.control_points();
  x[static_cast<std::size_t>(flat.flat_index(flat.num_u() - 2, 3))].z() += 0.01;
  const nurbs::NurbsSurface leader = test::with_points(flat, x);
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 10);
  EXPECT_NO_THROW(make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false, exact(Continuity::C0)));
  const std::string message = test::error_message(
      [&] { make_interface(leader, 0, Side::U1, follower, 1, Side::U0, false, exact(Continuity::C1)); });
  EXPECT_NE(message.find("reference rows are"), std::string::npos) << message;
  EXPECT_NE(message.find("least_squares"), std::string::npos) << message;
}

}  // namespace
}  // namespace shellfrac::coupling
