// Degree elevation (nurbs/degree_elevation.hpp): against the closed-form elevation of a Bezier segment,
// the classical cubic quarter circle, and the curve and surface evaluated before and after (1e-14).
#include "nurbs/degree_elevation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "nurbs/patch_builders.hpp"
#include "nurbs_test_helpers.hpp"

namespace shellfrac::nurbs {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(DegreeElevation, BezierSegmentMatchesTheClosedForm) {
  // One cubic Bezier segment raised to degree 4: Q_i = i/4 P_{i-1} + (1 - i/4) P_i (P&T Eq. 5.37 for
  // t = 1), a formula independent of the extraction and the least-squares inverse used here.
  const Vec3List P = {Vec3(0, 0, 0), Vec3(1, 2, 0.5), Vec3(3, -1, 2), Vec3(4, 1, -1)};
  const NurbsCurve c(KnotVector({0, 0, 0, 0, 1, 1, 1, 1}, 3), P, {1, 1, 1, 1});
  const NurbsCurve e = elevate_degree(c, 1);
  ASSERT_EQ(e.degree(), 4);
  ASSERT_EQ(e.control_points().size(), 5u);
  for (int i = 0; i <= 4; ++i) {
    const Vec3 expected = i == 0 ? P[0] : i == 4 ? P[3] : Vec3((i / 4.0) * P[i - 1] + (1 - i / 4.0) * P[i]);
    EXPECT_LE((e.control_points()[static_cast<size_t>(i)] - expected).norm(), 1e-14) << i;
  }
}

TEST(DegreeElevation, QuarterCircleBecomesTheKnownRationalCubic) {
  // The rational quadratic quarter circle (weights 1, sqrt(2)/2, 1) elevated to a cubic: control points
  // (1, 0), (1, 2 - sqrt(2)), (2 - sqrt(2), 1), (0, 1) with weights 1, (1 + sqrt(2))/3, (1 + sqrt(2))/3, 1.
  const double w = std::sqrt(0.5);
  const NurbsCurve arc(KnotVector({0, 0, 0, 1, 1, 1}, 2), {Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, {1, w, 1});
  const NurbsCurve e = elevate_degree(arc, 1);
  const double s = 2 - std::sqrt(2.0), wm = (1 + std::sqrt(2.0)) / 3;
  const Vec3List expected = {Vec3(1, 0, 0), Vec3(1, s, 0), Vec3(s, 1, 0), Vec3(0, 1, 0)};
  const std::vector<double> weights = {1, wm, wm, 1};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_LE((e.control_points()[i] - expected[i]).norm(), 1e-14) << i;
    EXPECT_NEAR(e.weights()[i], weights[i], 1e-14) << i;
  }
  for (int k = 0; k <= 100; ++k) EXPECT_NEAR(e.point(k / 100.0).norm(), 1.0, 1e-14);
}

// Largest distance between two curves over n + 1 parameters.
double curve_distance(const NurbsCurve& a, const NurbsCurve& b, int n) {
  double worst = 0;
  const double lo = a.knots().domain_begin(), hi = a.knots().domain_end();
  for (int k = 0; k <= n; ++k) {
    const double u = lo + (hi - lo) * k / n;
    worst = std::max(worst, (a.point(u) - b.point(u)).norm());
  }
  return worst;
}

TEST(DegreeElevation, RationalCurveWithRepeatedKnotsKeepsItsShapeAndContinuity) {
  // A random rational quartic on non-uniform knots with a double and a triple knot, raised by 1, 2, 3:
  // the same curve to 1e-14 of its size, every breakpoint's multiplicity raised by t (so its continuity
  // p - m is kept), and the first and second derivatives equal away from the breakpoints.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-1, 1), w(0.5, 2);
  const KnotVector kv({0, 0, 0, 0, 0, 0.1, 0.3, 0.3, 0.55, 0.7, 0.7, 0.7, 0.85, 1, 1, 1, 1, 1}, 4);
  Vec3List P;
  std::vector<double> W;
  for (int i = 0; i < kv.num_basis(); ++i) {
    P.emplace_back(x(rng), x(rng), x(rng));
    W.push_back(w(rng));
  }
  const NurbsCurve c(kv, P, W);
  for (int t : {1, 2, 3}) {
    const NurbsCurve e = elevate_degree(c, t);
    EXPECT_EQ(e.degree(), 4 + t);
    for (double b : kv.interior_breakpoints()) EXPECT_EQ(e.knots().multiplicity(b), kv.multiplicity(b) + t) << b;
    EXPECT_LE(curve_distance(c, e, 997), 1e-14) << t;
    for (double u : {0.05, 0.2, 0.42, 0.61, 0.77, 0.93}) {
      const CurvePoint a = c.evaluate(u), b = e.evaluate(u);
      EXPECT_LE((a.dx - b.dx).norm(), 1e-12 * (1 + a.dx.norm())) << t << " " << u;
      EXPECT_LE((a.ddx - b.ddx).norm(), 1e-11 * (1 + a.ddx.norm())) << t << " " << u;
    }
  }
}

TEST(DegreeElevation, SurfaceKeepsItsShape) {
  // A rational cone segment (quadratic arcs joined at double knots, refined) raised to (3, 4) and (4, 2).
  const NurbsSurface s = cone_segment(1.0, 0.4, 1.5, 1.4 * kPi, 5, 3);
  for (const auto& [tu, tv] : {std::pair{1, 2}, std::pair{2, 0}}) {
    const NurbsSurface e = elevate_degree(s, tu, tv);
    EXPECT_EQ(e.knots_u().degree(), s.knots_u().degree() + tu);
    EXPECT_EQ(e.knots_v().degree(), s.knots_v().degree() + tv);
    double worst = 0, normal = 0;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) {
        worst = std::max(worst, (s.point(i / 40.0, j / 40.0) - e.point(i / 40.0, j / 40.0)).norm());
        normal = std::max(normal, (s.normal(i / 40.0, j / 40.0) - e.normal(i / 40.0, j / 40.0)).norm());
      }
    EXPECT_LE(worst, 1e-14) << tu << " " << tv;
    EXPECT_LE(normal, 1e-12) << tu << " " << tv;
  }
}

TEST(DegreeElevation, NeedsAClampedKnotVectorAndAPositiveStep) {
  const KnotVector open({0, 0, 0, 0.5, 1, 1, 1}, 2);
  EXPECT_EQ(elevate_degree(open, 0).E.rows(), open.num_basis());
  EXPECT_NE(error_message([&] { elevate_degree(open, -1); }).find("t must be >= 0"), std::string::npos);
  const KnotVector periodic({-2, -1, 0, 1, 2, 3, 4}, 2);
  EXPECT_NE(error_message([&] { elevate_degree(periodic, 1); }).find("clamped"), std::string::npos);
}

}  // namespace
}  // namespace shellfrac::nurbs
