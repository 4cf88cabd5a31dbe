// Tests for NurbsCurve (evaluation, rational derivatives, validation) and circular_arc.
#include "nurbs/nurbs_curve.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "nurbs/bspline_basis.hpp"
#include "nurbs/nurbs_error.hpp"
#include "tests/nurbs/nurbs_test_helpers.hpp"

namespace shellfrac::nurbs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;

NurbsCurve sample_rational_cubic() {
  KnotVector kv({0, 0, 0, 0, 0.4, 0.7, 1, 1, 1, 1}, 3);
  Vec3List pts = {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 0.5, 2), Vec3(4, 3, -1), Vec3(5, 0, 0)};
  std::vector<double> w = {1.0, 0.5, 2.0, 1.5, 0.7, 1.0};
  return NurbsCurve(std::move(kv), std::move(pts), std::move(w));
}

TEST(NurbsCurve, PolynomialPointIsBasisCombination) {
  KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  Vec3List pts = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 1), Vec3(3, 2, 0), Vec3(4, 0, 0), Vec3(5, 1, 1)};
  const NurbsCurve c(kv, pts, std::vector<double>(6, 1.0));
  // At u = 2.5 the non-zero functions N_2, N_3, N_4 are 1/8, 6/8, 1/8 (see bspline_basis_test).
  const Vec3 expected = 0.125 * pts[2] + 0.75 * pts[3] + 0.125 * pts[4];
  EXPECT_LE((c.point(2.5) - expected).norm(), 1e-15);
  // Derivative from the hand-computed basis derivatives -1/2, 0, 1/2 and 1, -2, 1.
  const CurvePoint cp = c.evaluate(2.5);
  EXPECT_LE((cp.dx - (-0.5 * pts[2] + 0.5 * pts[4])).norm(), 1e-15);
  EXPECT_LE((cp.ddx - (pts[2] - 2.0 * pts[3] + pts[4])).norm(), 1e-14);
  // Clamped ends interpolate the end control points.
  EXPECT_LE((c.point(0.0) - pts.front()).norm(), 1e-15);
  EXPECT_LE((c.point(4.0) - pts.back()).norm(), 1e-15);
}

TEST(NurbsCurve, RationalPointMatchesDefinition) {
  const NurbsCurve c = sample_rational_cubic();
  for (double u : {0.0, 0.1, 0.4, 0.55, 0.9, 1.0}) {
    double N[4];
    const int span = bspline_basis_derivs(c.knots(), u, 0, N);
    Vec3 num = Vec3::Zero();
    double den = 0;
    for (int j = 0; j < 4; ++j) {
      const size_t i = static_cast<size_t>(span - 3 + j);
      num += N[j] * c.weights()[i] * c.control_points()[i];
      den += N[j] * c.weights()[i];
    }
    EXPECT_LE((c.point(u) - num / den).norm(), 1e-14) << "u=" << u;
    EXPECT_LE((c.evaluate(u).x - c.point(u)).norm(), 1e-15) << "u=" << u;
  }
}

TEST(NurbsCurve, RationalDerivativesMatchCentralDifferences) {
  const NurbsCurve c = sample_rational_cubic();
  const double h = 1e-6;
  for (double u : {0.05, 0.2, 0.33, 0.5, 0.61, 0.8, 0.95}) {
    const CurvePoint cp = c.evaluate(u);
    const Vec3 fd1 = (c.point(u + h) - c.point(u - h)) / (2 * h);
    const Vec3 fd2 = (c.evaluate(u + h).dx - c.evaluate(u - h).dx) / (2 * h);
    EXPECT_LE((cp.dx - fd1).norm(), 1e-6 * cp.dx.norm()) << "u=" << u;
    EXPECT_LE((cp.ddx - fd2).norm(), 1e-6 * cp.ddx.norm()) << "u=" << u;
  }
}

TEST(CircularArc, QuarterCircleIsExact) {
  const double r = 2.5;
  const NurbsCurve arc = circular_arc(r, 0.0, kPi / 2);
  ASSERT_EQ(arc.control_points().size(), 3u);
  EXPECT_EQ(arc.knots().knots(), (std::vector<double>{0, 0, 0, 1, 1, 1}));
  EXPECT_NEAR(arc.weights()[1], std::sqrt(0.5), 1e-16);
  EXPECT_LE((arc.control_points()[1] - Vec3(r, r, 0)).norm(), 1e-15 * r);
  double worst = 0;
  for (int s = 0; s <= 10000; ++s) {
    const Vec3 x = arc.point(s / 10000.0);
    worst = std::max(worst, std::abs(x.norm() - r));
    EXPECT_EQ(x.z(), 0.0);
  }
  EXPECT_LE(worst, 1e-14 * r);
  EXPECT_LE((arc.point(0.0) - Vec3(r, 0, 0)).norm(), 1e-15 * r);
  EXPECT_LE((arc.point(1.0) - Vec3(0, r, 0)).norm(), 1e-15 * r);
}

TEST(CircularArc, CurvatureAndTangentAreExact) {
  // Curvature |x' x x''| / |x'|^3 = 1/r everywhere, and the tangent is perpendicular to the radius;
  // this checks the rational first and second derivatives.
  const double r = 0.75;
  const NurbsCurve arc = circular_arc(r, 0.3, 5.0);
  for (int s = 0; s <= 400; ++s) {
    const CurvePoint c = arc.evaluate(s / 400.0);
    const double kappa = c.dx.cross(c.ddx).norm() / std::pow(c.dx.norm(), 3);
    EXPECT_NEAR(kappa, 1.0 / r, 1e-12 / r);
    EXPECT_NEAR(c.x.dot(c.dx), 0.0, 1e-13 * r * c.dx.norm());
    EXPECT_GT(c.x.cross(c.dx).z(), 0.0);  // counter-clockwise
  }
}

TEST(CircularArc, PieceCountsAndDoubleKnots) {
  struct Case {
    double sweep;
    int pieces;
  };
  for (const Case& c : {Case{kPi / 2, 1}, Case{kPi / 2 + 1e-3, 2}, Case{kPi, 2}, Case{1.5 * kPi, 3},
                        Case{1.5 * kPi + 1e-3, 4}, Case{2 * kPi, 4}, Case{0.1, 1}}) {
    const NurbsCurve arc = circular_arc(1.0, 0.0, c.sweep);
    EXPECT_EQ(arc.knots().num_spans(), c.pieces) << "sweep " << c.sweep;
    EXPECT_EQ(arc.control_points().size(), static_cast<size_t>(2 * c.pieces + 1));
    for (int k = 1; k < c.pieces; ++k) EXPECT_EQ(arc.knots().multiplicity(static_cast<double>(k) / c.pieces), 2);
    // Middle weight cos(half piece angle); middle point at radius 1 / cos(half piece angle).
    const double half = c.sweep / c.pieces / 2;
    EXPECT_NEAR(arc.weights()[1], std::cos(half), 1e-15);
    EXPECT_NEAR(arc.control_points()[1].norm(), 1.0 / std::cos(half), 1e-15);
    // Endpoint at the end angle.
    EXPECT_LE((arc.point(1.0) - Vec3(std::cos(c.sweep), std::sin(c.sweep), 0)).norm(), 1e-15);
  }
}

TEST(CircularArc, FullCircleIsClosedAndExact) {
  const double r = 1e3;
  const NurbsCurve circle = circular_arc(r, 0.7, 2 * kPi);
  EXPECT_EQ(circle.control_points().front(), circle.control_points().back());
  double worst = 0;
  for (int s = 0; s <= 20000; ++s) worst = std::max(worst, std::abs(circle.point(s / 20000.0).norm() - r));
  EXPECT_LE(worst, 1e-14 * r);
  // Quarter points at the piece joints.
  for (int k = 0; k <= 4; ++k) {
    const double a = 0.7 + k * kPi / 2;
    EXPECT_LE((circle.point(k / 4.0) - r * Vec3(std::cos(a), std::sin(a), 0)).norm(), 1e-14 * r);
  }
}

TEST(NurbsCurveValidation, ControlPointCount) {
  EXPECT_THAT(error_message([] {
                NurbsCurve(KnotVector({0, 0, 0, 1, 1, 1}, 2), Vec3List(4, Vec3::Zero()), std::vector<double>(4, 1.0));
              }),
              AllOf(HasSubstr("4 control points"), HasSubstr("requires 3")));
}

TEST(NurbsCurveValidation, WeightCount) {
  EXPECT_THAT(error_message([] {
                NurbsCurve(KnotVector({0, 0, 0, 1, 1, 1}, 2), Vec3List(3, Vec3::Zero()), std::vector<double>(2, 1.0));
              }),
              AllOf(HasSubstr("2 weights"), HasSubstr("3 control points")));
}

TEST(NurbsCurveValidation, NonPositiveOrNonFiniteWeight) {
  const KnotVector kv({0, 0, 0, 1, 1, 1}, 2);
  EXPECT_THAT(error_message([&] { NurbsCurve(kv, Vec3List(3, Vec3::Zero()), {1.0, 0.0, 1.0}); }),
              AllOf(HasSubstr("weight[1] = 0"), HasSubstr("finite and > 0")));
  EXPECT_THAT(error_message([&] { NurbsCurve(kv, Vec3List(3, Vec3::Zero()), {1.0, 1.0, -2.0}); }),
              HasSubstr("weight[2] = -2"));
  EXPECT_THAT(error_message([&] { NurbsCurve(kv, Vec3List(3, Vec3::Zero()), {std::nan(""), 1.0, 1.0}); }),
              HasSubstr("weight[0] = nan"));
}

TEST(NurbsCurveValidation, NonFiniteControlPoint) {
  Vec3List pts(3, Vec3::Zero());
  pts[2].y() = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_message([&] { NurbsCurve(KnotVector({0, 0, 0, 1, 1, 1}, 2), pts, {1, 1, 1}); }),
              AllOf(HasSubstr("control point[2]"), HasSubstr("not finite")));
}

TEST(NurbsCurveValidation, EvaluationOutsideDomain) {
  const NurbsCurve c = sample_rational_cubic();
  EXPECT_THAT(error_message([&] { c.point(1.5); }), AllOf(HasSubstr("parameter 1.5"), HasSubstr("[0, 1]")));
}

TEST(CircularArcValidation, BadArguments) {
  EXPECT_THAT(error_message([] { circular_arc(0.0, 0.0, 1.0); }), AllOf(HasSubstr("radius 0"), HasSubstr("> 0")));
  EXPECT_THAT(error_message([] { circular_arc(-1.0, 0.0, 1.0); }), HasSubstr("radius -1"));
  EXPECT_THAT(error_message([] { circular_arc(1.0, 0.0, 0.0); }),
              AllOf(HasSubstr("sweep 0"), HasSubstr("0 < sweep <= 2*pi")));
  EXPECT_THAT(error_message([] { circular_arc(1.0, 0.0, 7.0); }), HasSubstr("sweep 7 is invalid"));
  EXPECT_THAT(error_message([] { circular_arc(1.0, std::nan(""), 1.0); }), HasSubstr("start angle"));
  // A sweep of 2*pi plus round-off is accepted as a full circle.
  EXPECT_NO_THROW(circular_arc(1.0, 0.0, 2 * kPi * (1 + 1e-15)));
}

}  // namespace
}  // namespace shellfrac::nurbs
