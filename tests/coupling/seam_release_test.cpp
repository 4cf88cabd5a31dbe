// Exact closure across a crack (coupling::cut_exact_interface): each side of the crack keeps its own
// shared space, the follower's edge away from the crack is the leader's to round-off, and the two
// fragments' rows do not depend on each other.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "coupling/interface.hpp"
#include "coupling/row_projection.hpp"
#include "coupling/seam_release.hpp"
#include "nurbs/nurbs_curve.hpp"
#include "tests/coupling/coupling_test_helpers.hpp"

namespace shellfrac::coupling {
namespace {

using test::frame_at;

// Greville abscissae of a clamped quadratic uniform knot vector of `cells` spans on [0, 1]: the seam
// coordinates of the edge's control points.
std::vector<double> greville(int cells) {
  std::vector<double> knots{0, 0};
  for (int i = 0; i <= cells; ++i) knots.push_back(static_cast<double>(i) / cells);
  knots.push_back(1);
  knots.push_back(1);
  std::vector<double> g;
  for (int i = 0; i < cells + 2; ++i) g.push_back(0.5 * (knots[static_cast<size_t>(i + 1)] + knots[static_cast<size_t>(i + 2)]));
  return g;
}

nurbs::NurbsCurve edge_curve(int cells, const PointRows& rows, Eigen::Index first) {
  std::vector<double> knots{0, 0};
  for (int i = 0; i <= cells; ++i) knots.push_back(static_cast<double>(i) / cells);
  knots.push_back(1);
  knots.push_back(1);
  nurbs::Vec3List points;
  for (int k = 0; k < cells + 2; ++k) points.push_back(rows.row(first + k).transpose());
  return nurbs::NurbsCurve(nurbs::KnotVector(knots, 2), points, std::vector<double>(points.size(), 1.0));
}

struct CutSeam {
  Interface itf;
  SeamCut cut;
  nurbs::NurbsSurface leader;
};

CutSeam cut_8_10(double crack) {
  // 8 vs 10 cells along the seam (shared knots 0, 0.5, 1), C1, exact closure; leader on the left.
  CutSeam s{{}, {}, nurbs::flat_patch(1.0, 1.0, 4, 8, frame_at(Vec3(-1, 0, 0)))};
  const nurbs::NurbsSurface follower = nurbs::flat_patch(1.0, 1.0, 5, 10);
  InterfaceOptions o;
  o.continuity = Continuity::C1;
  o.closure = Closure::Exact;
  s.itf = make_interface(s.leader, 0, Side::U1, follower, 1, Side::U0, false, o);
  s.cut = cut_exact_interface(s.itf, greville(10), greville(8), {crack});
  return s;
}

// The leader's rows after the projection (random grid state), and the follower rows they give.
struct Rows {
  PointRows leader, follower;
};
Rows project(const CutSeam& s, const PointRows& grid_rows) {
  const Interface& c = s.cut.coupling;
  const RowProjection p(c, true, Eigen::VectorXd::Ones(20), Eigen::VectorXd::Zero(24));
  Rows r;
  r.leader = p.apply(grid_rows, PointRows::Zero(24, 3));
  nurbs::Vec3List x(s.leader.control_points().size(), Vec3::Zero());
  for (size_t j = 0; j < 10; ++j) {
    x[static_cast<size_t>(c.leader_row1[j])] = r.leader.row(static_cast<Eigen::Index>(j)).transpose();
    x[static_cast<size_t>(c.leader_row2[j])] = r.leader.row(static_cast<Eigen::Index>(10 + j)).transpose();
  }
  r.follower = c.follower_rows(x);
  return r;
}

TEST(ExactSeamCut, EachSideOfTheCrackStaysClosedToRoundOff) {
  const CutSeam s = cut_8_10(0.4);
  std::mt19937 rng(7);
  PointRows grid(20, 3);
  for (Eigen::Index k = 0; k < 20; ++k) grid.row(k) = test::random_vec(rng, 1.0);
  const Rows r = project(s, grid);
  // Row 1: the two edge curves coincide wherever both are more than two leader cells (0.25) from the
  // crack. Row 2 (C1): the follower's inward difference curve is D times the leader's outward one
  // (docs/coupling.md, "Matching condition"; D = h_eta / h_lambda is constant on flat patches).
  const nurbs::NurbsCurve l1 = edge_curve(8, r.leader, 0), f1 = edge_curve(10, r.follower, 0);
  const PointRows ldiff = r.leader.topRows(10) - r.leader.bottomRows(10);
  const PointRows fdiff = r.follower.bottomRows(12) - r.follower.topRows(12);
  const nurbs::NurbsCurve lt = edge_curve(8, ldiff, 0), ft = edge_curve(10, fdiff, 0);
  const double D = s.itf.D[0];
  double gap = 0, tangent = 0;
  int samples = 0;
  for (int i = 0; i <= 400; ++i) {
    const double t = i / 400.0;
    if (std::abs(t - 0.4) < 0.25) continue;
    ++samples;
    gap = std::max(gap, (l1.evaluate(t).x - f1.evaluate(t).x).norm());
    tangent = std::max(tangent, (D * lt.evaluate(t).x - ft.evaluate(t).x).norm());
  }
  std::printf("exact seam cut at 0.4: gap %.3g, tangent mismatch %.3g over %d samples\n", gap, tangent, samples);
  EXPECT_GT(samples, 200);
  EXPECT_LT(gap, 1e-13);  // round-off on unit-size random data
  EXPECT_LT(tangent, 1e-13);
}

TEST(ExactSeamCut, TheFragmentsRowsDoNotDependOnEachOther) {
  // Moving the grid state of the leader points beyond the crack changes nothing on this side: the
  // projection and the follower rows of one fragment see only its own leader points.
  const CutSeam s = cut_8_10(0.4);
  std::mt19937 rng(11);
  PointRows grid(20, 3);
  for (Eigen::Index k = 0; k < 20; ++k) grid.row(k) = test::random_vec(rng, 1.0);
  PointRows moved = grid;
  const std::vector<double> lg = greville(8), fg = greville(10);
  for (Eigen::Index j = 0; j < 10; ++j)
    if (lg[static_cast<size_t>(j)] > 0.4) {
      moved.row(j) += Vec3(0.3, -0.2, 0.5).transpose();
      moved.row(10 + j) += Vec3(-0.1, 0.4, 0.2).transpose();
    }
  const Rows a = project(s, grid), b = project(s, moved);
  double leader = 0, follower = 0;
  for (Eigen::Index j = 0; j < 10; ++j)
    if (lg[static_cast<size_t>(j)] < 0.4) {
      leader = std::max(leader, (a.leader.row(j) - b.leader.row(j)).norm());
      leader = std::max(leader, (a.leader.row(10 + j) - b.leader.row(10 + j)).norm());
    }
  for (Eigen::Index k = 0; k < 12; ++k)
    if (fg[static_cast<size_t>(k)] < 0.4) {
      follower = std::max(follower, (a.follower.row(k) - b.follower.row(k)).norm());
      follower = std::max(follower, (a.follower.row(12 + k) - b.follower.row(12 + k)).norm());
    }
  EXPECT_LT(leader, 1e-13);
  EXPECT_LT(follower, 1e-13);
  // Rigid motion of the whole seam is carried by every row (cut least-squares rows next to the crack too).
  PointRows rigid(20, 3);
  for (Eigen::Index k = 0; k < 20; ++k) rigid.row(k) = Vec3(0.1, -0.3, 0.7).transpose();
  const Rows c = project(s, rigid);
  EXPECT_LT((c.follower.rowwise() - Vec3(0.1, -0.3, 0.7).transpose()).rowwise().norm().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace shellfrac::coupling
