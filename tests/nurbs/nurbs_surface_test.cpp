// Tests for NurbsSurface: evaluation against the definition, rational derivatives and rational basis
// against finite differences, normals, validation.
#include "nurbs/nurbs_surface.hpp"

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

// A wavy rational surface: quadratic in u (5 functions), cubic in v (6 functions), non-uniform knots.
NurbsSurface wavy_rational_surface() {
  KnotVector ku({0, 0, 0, 0.3, 0.6, 1, 1, 1}, 2);
  KnotVector kv({-1, -1, -1, -1, 0, 0.5, 2, 2, 2, 2}, 3);
  Vec3List pts;
  std::vector<double> w;
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 5; ++i) {
      pts.emplace_back(i + 0.1 * j, j - 0.2 * i, std::sin(1.3 * i + 0.7 * j));
      w.push_back(1.0 + 0.4 * std::cos(2.1 * i - 1.1 * j));
    }
  }
  return NurbsSurface(std::move(ku), std::move(kv), std::move(pts), std::move(w));
}

// Direct evaluation of Eq. 2.37–2.38 from the 1D bases (reference for point()).
Vec3 reference_point(const NurbsSurface& s, double u, double v) {
  const int p = s.knots_u().degree(), q = s.knots_v().degree();
  std::vector<double> Nu(static_cast<size_t>(p + 1)), Nv(static_cast<size_t>(q + 1));
  const int su = bspline_basis_derivs(s.knots_u(), u, 0, Nu.data());
  const int sv = bspline_basis_derivs(s.knots_v(), v, 0, Nv.data());
  Vec3 num = Vec3::Zero();
  double den = 0;
  for (int b = 0; b <= q; ++b) {
    for (int a = 0; a <= p; ++a) {
      const size_t idx = static_cast<size_t>(s.flat_index(su - p + a, sv - q + b));
      const double f = Nu[static_cast<size_t>(a)] * Nv[static_cast<size_t>(b)] * s.weights()[idx];
      num += f * s.control_points()[idx];
      den += f;
    }
  }
  return num / den;
}

std::vector<std::pair<double, double>> interior_samples() {
  // Points kept more than 1e-4 from every knot line so that central differences stay in one cell.
  std::vector<std::pair<double, double>> uv;
  for (double u : {0.05, 0.17, 0.41, 0.52, 0.77, 0.93}) {
    for (double v : {-0.8, -0.3, 0.2, 0.45, 1.1, 1.9}) uv.emplace_back(u, v);
  }
  return uv;
}

TEST(NurbsSurface, PointMatchesDefinitionAndEvaluate) {
  const NurbsSurface s = wavy_rational_surface();
  EXPECT_TRUE(s.is_rational());
  EXPECT_EQ(s.num_u(), 5);
  EXPECT_EQ(s.num_v(), 6);
  EXPECT_EQ(s.flat_index(2, 3), 17);
  for (int a = 0; a <= 20; ++a) {
    for (int b = 0; b <= 20; ++b) {
      const double u = a / 20.0, v = -1.0 + 3.0 * b / 20.0;
      const Vec3 ref = reference_point(s, u, v);
      EXPECT_LE((s.point(u, v) - ref).norm(), 1e-14 * (1 + ref.norm()));
      EXPECT_LE((s.evaluate(u, v).x - ref).norm(), 1e-14 * (1 + ref.norm()));
    }
  }
  // Corners interpolate the corner control points (clamped knots).
  EXPECT_LE((s.point(0, -1) - s.control_points()[0]).norm(), 1e-15);
  EXPECT_LE((s.point(1, 2) - s.control_points()[29]).norm(), 1e-14);
}

TEST(NurbsSurface, RationalDerivativesMatchCentralDifferences) {
  const NurbsSurface s = wavy_rational_surface();
  const double h = 1e-6;
  for (const auto& [u, v] : interior_samples()) {
    const SurfacePoint sp = s.evaluate(u, v);
    const Vec3 fu = (s.point(u + h, v) - s.point(u - h, v)) / (2 * h);
    const Vec3 fv = (s.point(u, v + h) - s.point(u, v - h)) / (2 * h);
    const SurfacePoint pu = s.evaluate(u + h, v), mu = s.evaluate(u - h, v);
    const SurfacePoint pv = s.evaluate(u, v + h), mv = s.evaluate(u, v - h);
    const double scale1 = std::max(sp.du.norm(), sp.dv.norm());
    const double scale2 = std::max({sp.duu.norm(), sp.duv.norm(), sp.dvv.norm()});
    EXPECT_LE((sp.du - fu).norm(), 1e-6 * scale1) << u << "," << v;
    EXPECT_LE((sp.dv - fv).norm(), 1e-6 * scale1) << u << "," << v;
    EXPECT_LE((sp.duu - (pu.du - mu.du) / (2 * h)).norm(), 1e-6 * scale2) << u << "," << v;
    EXPECT_LE((sp.duv - (pv.du - mv.du) / (2 * h)).norm(), 1e-6 * scale2) << u << "," << v;
    EXPECT_LE((sp.duv - (pu.dv - mu.dv) / (2 * h)).norm(), 1e-6 * scale2) << u << "," << v;
    EXPECT_LE((sp.dvv - (pv.dv - mv.dv) / (2 * h)).norm(), 1e-6 * scale2) << u << "," << v;
  }
}

TEST(NurbsSurface, NormalIsUnitCrossOfTangents) {
  const NurbsSurface s = wavy_rational_surface();
  for (const auto& [u, v] : interior_samples()) {
    const SurfacePoint sp = s.evaluate(u, v);
    const Vec3 expected = sp.du.cross(sp.dv).normalized();
    EXPECT_LE((sp.normal - expected).norm(), 1e-14);
    EXPECT_NEAR(sp.normal.norm(), 1.0, 1e-15);
    EXPECT_LE((s.normal(u, v) - sp.normal).norm(), 1e-14);
  }
}

TEST(NurbsSurface, DegenerateNormalIsZero) {
  // All control points on the x-axis: du and dv are parallel, du x dv = 0 exactly.
  KnotVector k = KnotVector::open_uniform(2, 1);
  Vec3List pts;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) pts.emplace_back(i + 2.0 * j, 0, 0);
  }
  const NurbsSurface s(k, k, pts, std::vector<double>(9, 1.0));
  const SurfacePoint sp = s.evaluate(0.3, 0.6);
  EXPECT_EQ(sp.normal, Vec3::Zero());
  EXPECT_EQ(s.normal(0.3, 0.6), Vec3::Zero());
  EXPECT_GT(sp.du.norm(), 0.0);
}

TEST(NurbsSurface, PolynomialSurfaceIsNotRational) {
  KnotVector k = KnotVector::open_uniform(2, 2);
  const NurbsSurface s(k, k, Vec3List(16, Vec3::Ones()), std::vector<double>(16, 1.0));
  EXPECT_FALSE(s.is_rational());
  std::vector<double> w(16, 1.0);
  w[5] = 1.0000001;
  EXPECT_TRUE(NurbsSurface(k, k, Vec3List(16, Vec3::Ones()), w).is_rational());
}

TEST(RationalBasis, PartitionOfUnityAndReproduction) {
  const NurbsSurface s = wavy_rational_surface();
  SurfaceBasis basis;
  for (int a = 0; a <= 30; ++a) {
    for (int b = 0; b <= 30; ++b) {
      const double u = a / 30.0, v = -1.0 + 3.0 * b / 30.0;
      s.rational_basis(u, v, basis);
      ASSERT_EQ(basis.count, 3 * 4);
      double sum = 0, su = 0, sv = 0, suu = 0, suv = 0, svv = 0;
      Vec3 x = Vec3::Zero(), xu = Vec3::Zero(), xv = Vec3::Zero();
      for (int k = 0; k < basis.count; ++k) {
        const size_t kk = static_cast<size_t>(k);
        EXPECT_GE(basis.R[kk], 0.0);
        sum += basis.R[kk];
        su += basis.Ru[kk];
        sv += basis.Rv[kk];
        suu += basis.Ruu[kk];
        suv += basis.Ruv[kk];
        svv += basis.Rvv[kk];
        const Vec3& P = s.control_points()[static_cast<size_t>(basis.index[kk])];
        x += basis.R[kk] * P;
        xu += basis.Ru[kk] * P;
        xv += basis.Rv[kk] * P;
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      EXPECT_NEAR(su, 0.0, 1e-12);
      EXPECT_NEAR(sv, 0.0, 1e-12);
      EXPECT_NEAR(suu, 0.0, 1e-10);
      EXPECT_NEAR(suv, 0.0, 1e-10);
      EXPECT_NEAR(svv, 0.0, 1e-10);
      const SurfacePoint sp = s.evaluate(u, v);
      EXPECT_LE((x - sp.x).norm(), 1e-13);
      EXPECT_LE((xu - sp.du).norm(), 1e-12 * (1 + sp.du.norm()));
      EXPECT_LE((xv - sp.dv).norm(), 1e-12 * (1 + sp.dv.norm()));
    }
  }
}

TEST(RationalBasis, IndicesAreTheSupportInFlatOrder) {
  const NurbsSurface s = wavy_rational_surface();
  SurfaceBasis basis;
  s.rational_basis(0.45, 0.7, basis);  // u-span 3 (functions 1..3), v-span 5 (functions 2..5)
  ASSERT_EQ(basis.count, 12);
  int k = 0;
  for (int j = 2; j <= 5; ++j) {
    for (int i = 1; i <= 3; ++i, ++k) EXPECT_EQ(basis.index[static_cast<size_t>(k)], i + 5 * j);
  }
}

TEST(RationalBasis, DerivativesMatchCentralDifferences) {
  const NurbsSurface s = wavy_rational_surface();
  const double h = 1e-6;
  SurfaceBasis at, pu, mu, pv, mv;
  for (const auto& [u, v] : interior_samples()) {
    s.rational_basis(u, v, at);
    s.rational_basis(u + h, v, pu);
    s.rational_basis(u - h, v, mu);
    s.rational_basis(u, v + h, pv);
    s.rational_basis(u, v - h, mv);
    double scale1 = 0, scale2 = 0;
    for (int k = 0; k < at.count; ++k) {
      const size_t kk = static_cast<size_t>(k);
      scale1 = std::max({scale1, std::abs(at.Ru[kk]), std::abs(at.Rv[kk])});
      scale2 = std::max({scale2, std::abs(at.Ruu[kk]), std::abs(at.Ruv[kk]), std::abs(at.Rvv[kk])});
    }
    for (int k = 0; k < at.count; ++k) {
      const size_t kk = static_cast<size_t>(k);
      ASSERT_EQ(pu.index[kk], at.index[kk]);  // same cell
      EXPECT_NEAR(at.Ru[kk], (pu.R[kk] - mu.R[kk]) / (2 * h), 1e-6 * scale1);
      EXPECT_NEAR(at.Rv[kk], (pv.R[kk] - mv.R[kk]) / (2 * h), 1e-6 * scale1);
      EXPECT_NEAR(at.Ruu[kk], (pu.Ru[kk] - mu.Ru[kk]) / (2 * h), 1e-6 * scale2);
      EXPECT_NEAR(at.Ruv[kk], (pv.Ru[kk] - mv.Ru[kk]) / (2 * h), 1e-6 * scale2);
      EXPECT_NEAR(at.Rvv[kk], (pv.Rv[kk] - mv.Rv[kk]) / (2 * h), 1e-6 * scale2);
    }
  }
}

TEST(RationalBasis, BuffersAreReusedBetweenCalls) {
  const NurbsSurface s = wavy_rational_surface();
  SurfaceBasis basis;
  s.rational_basis(0.2, 0.3, basis);
  const double* r = basis.R.data();
  const double* rvv = basis.Rvv.data();
  const int* idx = basis.index.data();
  s.rational_basis(0.9, 1.7, basis);
  EXPECT_EQ(basis.R.data(), r);
  EXPECT_EQ(basis.Rvv.data(), rvv);
  EXPECT_EQ(basis.index.data(), idx);
}

TEST(NurbsSurfaceValidation, ControlNetSize) {
  KnotVector k = KnotVector::open_uniform(3, 1);  // 4 basis functions per direction
  EXPECT_THAT(error_message([&] { NurbsSurface(k, k, Vec3List(12, Vec3::Zero()), std::vector<double>(12, 1.0)); }),
              HasSubstr("control net has 12 points but knots and degrees require 4 x 4 = 16"));
}

TEST(NurbsSurfaceValidation, WeightCount) {
  KnotVector k = KnotVector::open_uniform(2, 1);
  EXPECT_THAT(error_message([&] { NurbsSurface(k, k, Vec3List(9, Vec3::Zero()), std::vector<double>(8, 1.0)); }),
              AllOf(HasSubstr("8 weights"), HasSubstr("9 control points")));
}

TEST(NurbsSurfaceValidation, BadWeights) {
  KnotVector k = KnotVector::open_uniform(2, 1);
  std::vector<double> w(9, 1.0);
  w[7] = -0.5;  // (i, j) = (1, 2)
  EXPECT_THAT(error_message([&] { NurbsSurface(k, k, Vec3List(9, Vec3::Zero()), w); }),
              AllOf(HasSubstr("weight (1, 2) = -0.5"), HasSubstr("finite and > 0")));
  w[7] = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_message([&] { NurbsSurface(k, k, Vec3List(9, Vec3::Zero()), w); }),
              HasSubstr("weight (1, 2) = inf"));
}

TEST(NurbsSurfaceValidation, NonFiniteControlPoint) {
  KnotVector k = KnotVector::open_uniform(2, 1);
  Vec3List pts(9, Vec3::Zero());
  pts[4].x() = std::nan("");
  EXPECT_THAT(error_message([&] { NurbsSurface(k, k, pts, std::vector<double>(9, 1.0)); }),
              AllOf(HasSubstr("control point (1, 1)"), HasSubstr("not finite")));
}

TEST(NurbsSurfaceValidation, EvaluationOutsideDomain) {
  const NurbsSurface s = wavy_rational_surface();
  EXPECT_THAT(error_message([&] { s.evaluate(0.5, 2.5); }), AllOf(HasSubstr("parameter 2.5"), HasSubstr("[-1, 2]")));
  SurfaceBasis b;
  EXPECT_THROW(s.rational_basis(-0.1, 0.0, b), NurbsError);
}

}  // namespace
}  // namespace shellfrac::nurbs
