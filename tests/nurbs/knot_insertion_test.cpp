// Tests for knot insertion (thesis appendix D): geometry unchanged, A and U properties, validation.
#include "nurbs/knot_insertion.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "nurbs/nurbs_error.hpp"
#include "nurbs/patch_builders.hpp"
#include "tests/nurbs/nurbs_test_helpers.hpp"

namespace shellfrac::nurbs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;

NurbsCurve cubic_curve(bool rational) {
  KnotVector kv({0, 0, 0, 0, 0.25, 0.6, 1, 1, 1, 1}, 3);
  Vec3List pts = {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 0.5, 2), Vec3(4, 3, -1), Vec3(5, 0, 0)};
  std::vector<double> w = rational ? std::vector<double>{1.0, 0.5, 2.0, 1.5, 0.7, 1.0} : std::vector<double>(6, 1.0);
  return NurbsCurve(std::move(kv), std::move(pts), std::move(w));
}

double max_deviation(const NurbsCurve& a, const NurbsCurve& b, int samples = 2000) {
  double worst = 0;
  const double lo = a.knots().domain_begin(), hi = a.knots().domain_end();
  for (int s = 0; s <= samples; ++s) {
    const double u = lo + (hi - lo) * s / samples;
    worst = std::max(worst, (a.point(u) - b.point(u)).norm());
  }
  return worst;
}

double max_deviation(const NurbsSurface& a, const NurbsSurface& b, int samples = 60) {
  double worst = 0;
  const KnotVector &ku = a.knots_u(), &kv = a.knots_v();
  for (int i = 0; i <= samples; ++i) {
    for (int j = 0; j <= samples; ++j) {
      const double u = ku.domain_begin() + (ku.domain_end() - ku.domain_begin()) * i / samples;
      const double v = kv.domain_begin() + (kv.domain_end() - kv.domain_begin()) * j / samples;
      worst = std::max(worst, (a.point(u, v) - b.point(u, v)).norm());
    }
  }
  return worst;
}

Eigen::VectorXd row_sums(const SparseMatrix& m) { return m * Eigen::VectorXd::Ones(m.cols()); }

Eigen::MatrixXd as_matrix(const Vec3List& pts) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(pts.size()), 3);
  for (size_t i = 0; i < pts.size(); ++i) m.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  return m;
}

TEST(KnotInsertion, BezierMidpointMatchesBoehmByHand) {
  // Quadratic Bezier [0,0,0,1,1,1] + knot 0.5: Q0 = P0, Q1 = (P0+P1)/2, Q2 = (P1+P2)/2, Q3 = P2.
  const KnotVector kv({0, 0, 0, 1, 1, 1}, 2);
  const CurveRefinement r = refine_knots(kv, {1, 1, 1}, {0.5});
  Eigen::MatrixXd expected(4, 3);
  expected << 1, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0.5, 0, 0, 1;
  EXPECT_EQ(Eigen::MatrixXd(r.A), expected);
  EXPECT_EQ(Eigen::MatrixXd(r.U), expected);
  EXPECT_EQ(r.knots.knots(), (std::vector<double>{0, 0, 0, 0.5, 1, 1, 1}));
  EXPECT_EQ(r.weights, (std::vector<double>{1, 1, 1, 1}));
}

TEST(KnotInsertion, PolynomialCurveUnchangedSingleAndMultiple) {
  const NurbsCurve c = cubic_curve(false);
  for (const std::vector<double>& ins : std::vector<std::vector<double>>{
           {0.5}, {0.1, 0.9, 0.3, 0.45, 0.7}, {0.25}, {0.25, 0.25}, {0.4, 0.4, 0.4}, {0.0001, 0.9999}}) {
    const NurbsCurve r = insert_knots(c, ins);
    EXPECT_EQ(r.knots().num_basis(), c.knots().num_basis() + static_cast<int>(ins.size()));
    EXPECT_LE(max_deviation(c, r), 1e-12);
    for (double w : r.weights()) EXPECT_EQ(w, 1.0);  // stays polynomial exactly
  }
}

TEST(KnotInsertion, RationalCurveUnchanged) {
  const NurbsCurve c = cubic_curve(true);
  for (const std::vector<double>& ins :
       std::vector<std::vector<double>>{{0.5}, {0.8, 0.1, 0.33}, {0.6, 0.6}, {0.2, 0.2, 0.2, 0.9}}) {
    const NurbsCurve r = insert_knots(c, ins);
    EXPECT_LE(max_deviation(c, r), 1e-12);
    // The rational derivative is also unchanged (same parameterisation).
    for (double u : {0.13, 0.5, 0.77}) {
      EXPECT_LE((c.evaluate(u).dx - r.evaluate(u).dx).norm(), 1e-11 * c.evaluate(u).dx.norm());
    }
  }
}

TEST(KnotInsertion, CircleStaysExact) {
  const double radius = 3.0;
  const NurbsCurve circle = circular_arc(radius, 0.0, 2 * kPi);
  const NurbsCurve r = insert_knots(circle, {0.1, 0.125, 0.3, 0.3, 0.61, 0.9});
  EXPECT_LE(max_deviation(circle, r), 1e-12);
  double worst = 0;
  for (int s = 0; s <= 5000; ++s) worst = std::max(worst, std::abs(r.point(s / 5000.0).norm() - radius));
  EXPECT_LE(worst, 1e-14 * radius);
}

TEST(KnotInsertion, MatricesReproduceControlPointsAndAreAffine) {
  const NurbsCurve c = cubic_curve(true);
  const std::vector<double> ins = {0.7, 0.1, 0.25, 0.5, 0.5};
  const CurveRefinement ref = refine_knots(c.knots(), c.weights(), ins);
  const NurbsCurve r = insert_knots(c, ins);
  const int n = c.knots().num_basis();
  ASSERT_EQ(ref.A.rows(), n + 5);
  ASSERT_EQ(ref.A.cols(), n);
  ASSERT_EQ(ref.U.rows(), n + 5);
  EXPECT_EQ(ref.knots.knots(), r.knots().knots());

  // Rows of A and U sum to 1; A entries lie in [0, 1].
  const Eigen::VectorXd ra = row_sums(ref.A), ru = row_sums(ref.U);
  for (Eigen::Index i = 0; i < ra.size(); ++i) {
    EXPECT_NEAR(ra[i], 1.0, 1e-14);
    EXPECT_NEAR(ru[i], 1.0, 1e-14);
  }
  for (int k = 0; k < ref.A.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(ref.A, k); it; ++it) {
      EXPECT_GE(it.value(), 0.0);
      EXPECT_LE(it.value(), 1.0);
    }
  }
  // New weights = A w; U = W_new^-1 A W; Q = U P.
  const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(c.weights().data(), n);
  const Eigen::VectorXd aw = ref.A * w;
  for (int i = 0; i < n + 5; ++i) EXPECT_NEAR(ref.weights[static_cast<size_t>(i)], aw[i], 1e-15);
  const Eigen::MatrixXd U_expected =
      Eigen::VectorXd(aw.cwiseInverse()).asDiagonal() * Eigen::MatrixXd(ref.A) * w.asDiagonal();
  EXPECT_LE((Eigen::MatrixXd(ref.U) - U_expected).cwiseAbs().maxCoeff(), 1e-15);
  const Eigen::MatrixXd Q = ref.U * as_matrix(c.control_points());
  EXPECT_LE((Q - as_matrix(r.control_points())).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(r.weights(), ref.weights);
}

TEST(KnotInsertion, EmptyInsertIsIdentity) {
  const NurbsCurve c = cubic_curve(true);
  const CurveRefinement ref = refine_knots(c.knots(), c.weights(), {});
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(6, 6);
  EXPECT_EQ(Eigen::MatrixXd(ref.A), I);
  EXPECT_LE((Eigen::MatrixXd(ref.U) - I).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(ref.weights, c.weights());
  EXPECT_EQ(ref.knots.knots(), c.knots().knots());
}

TEST(KnotInsertion, UpToDegreeMultiplicityIsAllowed) {
  // Existing knot 0.25 (multiplicity 1) can be raised to 3 = degree; the curve becomes C0 there.
  const NurbsCurve c = cubic_curve(true);
  const NurbsCurve r = insert_knots(c, {0.25, 0.25});
  EXPECT_EQ(r.knots().multiplicity(0.25), 3);
  EXPECT_LE(max_deviation(c, r), 1e-12);
  // With multiplicity p the curve interpolates a control point at the knot.
  EXPECT_LE((r.point(0.25) - r.control_points()[3]).norm(), 1e-13);
}

TEST(KnotInsertion, UnclampedVectorAtDomainEnds) {
  // Uniform (unclamped) quadratic: domain [knots[2], knots[4]] = [2, 4]. Inserting the domain ends
  // (multiplicity 1 -> 2) keeps the domain and the curve.
  KnotVector kv({0, 1, 2, 3, 4, 5, 6}, 2);
  const NurbsCurve c(kv, {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 1, 2)}, {1.0, 0.5, 2.0, 1.0});
  const NurbsCurve r = insert_knots(c, {4.0, 2.0, 3.0});
  EXPECT_EQ(r.knots().knots(), (std::vector<double>{0, 1, 2, 2, 3, 3, 4, 4, 5, 6}));
  EXPECT_EQ(r.knots().domain_begin(), 2.0);
  EXPECT_EQ(r.knots().domain_end(), 4.0);
  EXPECT_LE(max_deviation(c, r), 1e-12);
}

TEST(KnotInsertion, PolynomialSurfaceUnchanged) {
  KnotVector ku({0, 0, 0, 0.5, 1, 1, 1}, 2);
  KnotVector kv({0, 0, 0, 0, 1, 1, 1, 1}, 3);
  Vec3List pts;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) pts.emplace_back(i, j, std::cos(i + 2.0 * j));
  }
  const NurbsSurface s(ku, kv, pts, std::vector<double>(16, 1.0));
  const SurfaceRefinement r = insert_knots(s, {0.25, 0.75, 0.75}, {0.4, 0.4, 0.6});
  EXPECT_FALSE(r.surface.is_rational());
  EXPECT_EQ(r.surface.num_u(), 7);
  EXPECT_EQ(r.surface.num_v(), 7);
  EXPECT_LE(max_deviation(s, r.surface), 1e-12);
}

TEST(KnotInsertion, RationalSurfaceUnchangedAndMatrixConsistent) {
  const NurbsSurface s = cylinder_segment(2.0, 3.0, 2 * kPi, 4, 2);
  ASSERT_TRUE(s.is_rational());
  const std::vector<double> iu = {0.1, 0.3, 0.3, 0.8}, iv = {0.25, 0.9};
  const SurfaceRefinement r = insert_knots(s, iu, iv);
  EXPECT_EQ(r.surface.num_u(), s.num_u() + 4);
  EXPECT_EQ(r.surface.num_v(), s.num_v() + 2);
  EXPECT_LE(max_deviation(s, r.surface), 1e-12);

  // Q = U P, rows of U sum to 1, and W_new = kron(A_v, A_u) w.
  const Eigen::MatrixXd Q = r.U * as_matrix(s.control_points());
  EXPECT_LE((Q - as_matrix(r.surface.control_points())).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::VectorXd ru = row_sums(r.U);
  for (Eigen::Index i = 0; i < ru.size(); ++i) EXPECT_NEAR(ru[i], 1.0, 1e-14);
  const CurveRefinement au = refine_knots(s.knots_u(), std::vector<double>(static_cast<size_t>(s.num_u()), 1.0), iu);
  const CurveRefinement av = refine_knots(s.knots_v(), std::vector<double>(static_cast<size_t>(s.num_v()), 1.0), iv);
  const Eigen::MatrixXd Au(au.A), Av(av.A);
  const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(s.weights().data(), s.num_u() * s.num_v());
  Eigen::VectorXd w_new = Eigen::VectorXd::Zero(Au.rows() * Av.rows());
  for (Eigen::Index jn = 0; jn < Av.rows(); ++jn) {
    for (Eigen::Index in = 0; in < Au.rows(); ++in) {
      for (Eigen::Index j = 0; j < Av.cols(); ++j) {
        for (Eigen::Index i = 0; i < Au.cols(); ++i) {
          w_new[in + Au.rows() * jn] += Av(jn, j) * Au(in, i) * w[i + Au.cols() * j];
        }
      }
    }
  }
  for (Eigen::Index k = 0; k < w_new.size(); ++k) {
    EXPECT_NEAR(r.surface.weights()[static_cast<size_t>(k)], w_new[k], 1e-15);
  }
}

TEST(KnotInsertion, SurfaceOneDirectionOnly) {
  const NurbsSurface s = cone_segment(1.0, 0.5, 2.0, kPi, 2, 1);
  const SurfaceRefinement ru = insert_knots(s, {0.2}, {});
  EXPECT_EQ(ru.surface.num_u(), s.num_u() + 1);
  EXPECT_EQ(ru.surface.num_v(), s.num_v());
  EXPECT_LE(max_deviation(s, ru.surface), 1e-12);
  const SurfaceRefinement rv = insert_knots(s, {}, {0.3, 0.6});
  EXPECT_EQ(rv.surface.num_v(), s.num_v() + 2);
  EXPECT_LE(max_deviation(s, rv.surface), 1e-12);
  const SurfaceRefinement none = insert_knots(s, {}, {});
  EXPECT_EQ(none.surface.control_points(), s.control_points());
  EXPECT_EQ(none.surface.weights(), s.weights());
}

TEST(KnotInsertionValidation, MultiplicityAboveDegree) {
  const KnotVector kv({0, 0, 0, 0.5, 0.5, 1, 1, 1}, 2);
  EXPECT_THAT(error_message([&] { refine_knots(kv, std::vector<double>(5, 1.0), {0.5}); }),
              AllOf(HasSubstr("inserting knot 0.5 would raise its multiplicity to 3"),
                    HasSubstr("the degree 2 allows at most 2")));
  // Twice in one list.
  EXPECT_THAT(error_message([&] { refine_knots(kv, std::vector<double>(5, 1.0), {0.3, 0.3, 0.3}); }),
              HasSubstr("inserting knot 0.3 would raise its multiplicity to 3"));
  // The clamped end knots already have multiplicity p+1.
  EXPECT_THAT(error_message([&] { refine_knots(kv, std::vector<double>(5, 1.0), {1.0}); }),
              HasSubstr("multiplicity to 4"));
}

TEST(KnotInsertionValidation, OutsideDomainOrNotFinite) {
  const NurbsCurve c = cubic_curve(false);
  EXPECT_THAT(error_message([&] { insert_knots(c, {0.5, 1.5}); }),
              AllOf(HasSubstr("knot to insert 1.5"), HasSubstr("outside the knot domain [0, 1]")));
  EXPECT_THAT(error_message([&] { insert_knots(c, {-0.1}); }), HasSubstr("knot to insert -0.1"));
  EXPECT_THAT(error_message([&] { insert_knots(c, {0.2, std::nan(""), 0.3}); }), HasSubstr("knot to insert nan"));
}

TEST(KnotInsertionValidation, WeightsMismatch) {
  const KnotVector kv({0, 0, 0, 1, 1, 1}, 2);
  EXPECT_THAT(error_message([&] { refine_knots(kv, {1.0, 1.0}, {0.5}); }),
              AllOf(HasSubstr("got 2 weights"), HasSubstr("3 basis functions")));
  EXPECT_THAT(error_message([&] { refine_knots(kv, {1.0, 0.0, 1.0}, {0.5}); }),
              AllOf(HasSubstr("weight[1] = 0"), HasSubstr("finite and > 0")));
}

TEST(KnotInsertionValidation, SurfaceDirectionErrors) {
  const NurbsSurface s = flat_patch(1.0, 1.0, 2, 2);  // interior knot 0.5 with multiplicity 1
  EXPECT_THROW(insert_knots(s, {0.5, 0.5}, {}), NurbsError);
  EXPECT_THROW(insert_knots(s, {}, {2.0}), NurbsError);
}

}  // namespace
}  // namespace shellfrac::nurbs
