// Tests for bspline_basis_derivs: hand-computed values, an independent recursive reference,
// partition of unity, finite differences and high degrees.
#include "nurbs/bspline_basis.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {
namespace {

using ::testing::HasSubstr;

// Independent reference: textbook Cox–de Boor recursion (thesis Eq. 2.32–2.33) with 0/0 := 0, and the
// derivative recursion of Eq. 2.35. Exponential cost, fine for tests. `end` is the clamped domain end.
double ref_basis(const std::vector<double>& U, int i, int p, double u, double end) {
  if (p == 0) {
    const double a = U[static_cast<size_t>(i)], b = U[static_cast<size_t>(i) + 1];
    if (a <= u && u < b) return 1.0;
    // Close the last non-empty span at the (clamped) domain end so that u == end evaluates like find_span.
    return (a < b && u == b && b == end) ? 1.0 : 0.0;
  }
  double value = 0.0;
  const double d1 = U[static_cast<size_t>(i + p)] - U[static_cast<size_t>(i)];
  const double d2 = U[static_cast<size_t>(i + p + 1)] - U[static_cast<size_t>(i + 1)];
  if (d1 > 0) value += (u - U[static_cast<size_t>(i)]) / d1 * ref_basis(U, i, p - 1, u, end);
  if (d2 > 0) value += (U[static_cast<size_t>(i + p + 1)] - u) / d2 * ref_basis(U, i + 1, p - 1, u, end);
  return value;
}

double ref_deriv(const std::vector<double>& U, int i, int p, int k, double u, double end) {
  if (k == 0) return ref_basis(U, i, p, u, end);
  if (p == 0) return 0.0;
  double value = 0.0;
  const double d1 = U[static_cast<size_t>(i + p)] - U[static_cast<size_t>(i)];
  const double d2 = U[static_cast<size_t>(i + p + 1)] - U[static_cast<size_t>(i + 1)];
  if (d1 > 0) value += p / d1 * ref_deriv(U, i, p - 1, k - 1, u, end);
  if (d2 > 0) value -= p / d2 * ref_deriv(U, i + 1, p - 1, k - 1, u, end);
  return value;
}

std::vector<double> eval(const KnotVector& kv, double u, int max_deriv, int* span_out = nullptr) {
  std::vector<double> out(static_cast<size_t>((max_deriv + 1) * (kv.degree() + 1)));
  const int span = bspline_basis_derivs(kv, u, max_deriv, out.data());
  if (span_out) *span_out = span;
  return out;
}

// Dense samples of the domain that stay at least `gap` away from every knot (for finite differences).
std::vector<double> samples_away_from_knots(const KnotVector& kv, int per_span, double gap) {
  std::vector<double> us;
  for (int i = kv.degree(); i < kv.num_basis(); ++i) {
    const double a = kv[i], b = kv[i + 1];
    if (!(a < b)) continue;
    for (int s = 0; s < per_span; ++s) {
      const double t = (s + 0.5) / per_span;
      const double u = a + t * (b - a);
      if (u - a > gap && b - u > gap) us.push_back(u);
    }
  }
  return us;
}

// Quadratic, knots [0,0,0,1,2,3,4,4,4], u = 2.5 (span 4, functions N_2, N_3, N_4), t = u - 2 = 1/2.
// N_2 and N_3 have uniform knots there:  N_2 = (1-t)^2/2, N_3 = (-2t^2 + 2t + 1)/2.
// N_4 on [2,3] from Cox–de Boor with knots [2,3,4,4]: N_4 = (u-2)/2 * (u-2) = t^2/2.
//   values: 1/8, 6/8, 1/8;  d/du: -(1-t) = -1/2, 1 - 2t = 0, t = 1/2;  d2/du2: 1, -2, 1.
TEST(BsplineBasis, QuadraticHandComputedInteriorSpan) {
  const KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  int span = -1;
  const std::vector<double> out = eval(kv, 2.5, 2, &span);
  EXPECT_EQ(span, 4);
  const std::vector<double> expected = {0.125, 0.75, 0.125, -0.5, 0.0, 0.5, 1.0, -2.0, 1.0};
  ASSERT_EQ(out.size(), expected.size());
  for (size_t k = 0; k < out.size(); ++k) EXPECT_NEAR(out[k], expected[k], 1e-15) << "entry " << k;
}

// Same knots, u = 3.5 (span 5, functions N_3, N_4, N_5), s = u - 3 = 1/2; the end knot is repeated.
// N_3 (uniform knots 1..4), last piece: (1-s)^2/2            -> 1/8,  d = -(1-s) = -1/2, d2 = 1
// N_5 (knots [3,4,4,4]): (u-3)/(4-3) * (u-3) = s^2            -> 1/4,  d = 2s = 1,       d2 = 2
// N_4 (knots [2,3,4,4]): (u-2)/2 (4-u) + (4-u)(u-3)          -> 5/8,  d = -1/2,         d2 = -3
TEST(BsplineBasis, QuadraticHandComputedEndSpan) {
  const KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  int span = -1;
  const std::vector<double> out = eval(kv, 3.5, 2, &span);
  EXPECT_EQ(span, 5);
  const std::vector<double> expected = {0.125, 0.625, 0.25, -0.5, -0.5, 1.0, 1.0, -3.0, 2.0};
  for (size_t k = 0; k < out.size(); ++k) EXPECT_NEAR(out[k], expected[k], 1e-15) << "entry " << k;
}

// Cubic with uniform knots around span 6 of [0,0,0,0,1,2,3,4,5,6,7,7,7,7] at u = 3.5 (t = 1/2):
// uniform cubic pieces (1-t)^3/6, (3t^3-6t^2+4)/6, (-3t^3+3t^2+3t+1)/6, t^3/6
//   values   : 1/48, 23/48, 23/48, 1/48
//   d/du     : -(1-t)^2/2 = -1/8, (9t^2-12t)/6 = -5/8, (-9t^2+6t+3)/6 = 5/8, t^2/2 = 1/8
//   d2/du2   : (1-t) = 1/2, (18t-12)/6 = -1/2, (-18t+6)/6 = -1/2, t = 1/2
//   d3/du3   : -1, 3, -3, 1;  d4/du4 = 0 (above the degree)
TEST(BsplineBasis, CubicHandComputed) {
  const KnotVector kv({0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7}, 3);
  int span = -1;
  const std::vector<double> out = eval(kv, 3.5, 4, &span);
  EXPECT_EQ(span, 6);
  const std::vector<double> expected = {1.0 / 48, 23.0 / 48, 23.0 / 48, 1.0 / 48,  // values
                                        -0.125,   -0.625,    0.625,     0.125,     // first
                                        0.5,      -0.5,      -0.5,      0.5,       // second
                                        -1,       3,         -3,        1,         // third
                                        0,        0,         0,         0};        // fourth
  ASSERT_EQ(out.size(), expected.size());
  for (size_t k = 0; k < out.size(); ++k) EXPECT_NEAR(out[k], expected[k], 1e-15) << "entry " << k;
}

TEST(BsplineBasis, CubicAtDomainEndInterpolates) {
  const KnotVector kv({0, 0, 0, 0, 1, 2, 3, 3, 3, 3}, 3);
  int span = -1;
  const std::vector<double> out = eval(kv, 3.0, 1, &span);
  EXPECT_EQ(span, 5);
  EXPECT_NEAR(out[0], 0.0, 1e-15);
  EXPECT_NEAR(out[1], 0.0, 1e-15);
  EXPECT_NEAR(out[2], 0.0, 1e-15);
  EXPECT_NEAR(out[3], 1.0, 1e-15);
  // Derivative of the last function at a clamped end: p / (u_n - u_{n-1}) = 3 / 1.
  EXPECT_NEAR(out[4 + 3], 3.0, 1e-14);
  EXPECT_NEAR(out[4 + 2], -3.0, 1e-14);
}

TEST(BsplineBasis, MatchesRecursiveReferenceOnNonUniformKnots) {
  const std::vector<std::pair<std::vector<double>, int>> cases = {
      {{0, 0, 0, 0.3, 0.35, 1.2, 2.0, 2.0, 2.0}, 2},
      {{-1, -1, -1, -1, -0.2, 0.5, 0.5, 0.9, 3, 3, 3, 3}, 3},
      {{0, 0, 0, 0, 0, 0.1, 0.4, 0.4, 0.4, 0.45, 1, 1, 1, 1, 1}, 4},
  };
  for (const auto& [knots, p] : cases) {
    const KnotVector kv(knots, p);
    const double lo = kv.domain_begin(), hi = kv.domain_end();
    for (int s = 0; s <= 200; ++s) {
      const double u = lo + (hi - lo) * s / 200.0;
      int span = -1;
      const std::vector<double> out = eval(kv, u, p + 1, &span);
      for (int k = 0; k <= std::min(p, 2); ++k) {
        for (int j = 0; j <= p; ++j) {
          const double ref = ref_deriv(knots, span - p + j, p, k, u, hi);
          EXPECT_NEAR(out[static_cast<size_t>(k * (p + 1) + j)], ref, 1e-12 * std::max(1.0, std::abs(ref)))
              << "p=" << p << " u=" << u << " k=" << k << " j=" << j;
        }
      }
      for (int j = 0; j <= p; ++j) EXPECT_EQ(out[static_cast<size_t>((p + 1) * (p + 1) + j)], 0.0);
    }
  }
}

TEST(BsplineBasis, PartitionOfUnityNonNegativityAndZeroDerivativeSums) {
  for (int p = 1; p <= 5; ++p) {
    const KnotVector kv({0, 0, 0, 0, 0, 0, 0.1, 0.25, 0.25, 0.6, 0.61, 1, 1, 1, 1, 1, 1}, 5);
    const KnotVector use = p == 5 ? kv : KnotVector::open_uniform(p, 7, -3.0, 4.0);
    const double lo = use.domain_begin(), hi = use.domain_end();
    for (int s = 0; s <= 1000; ++s) {
      const double u = lo + (hi - lo) * s / 1000.0;
      const std::vector<double> out = eval(use, u, 2);
      const int P = use.degree() + 1;
      double sum = 0, dsum = 0, ddsum = 0, dscale = 0, ddscale = 0;
      for (int j = 0; j < P; ++j) {
        EXPECT_GE(out[static_cast<size_t>(j)], 0.0);
        sum += out[static_cast<size_t>(j)];
        dsum += out[static_cast<size_t>(P + j)];
        ddsum += out[static_cast<size_t>(2 * P + j)];
        dscale = std::max(dscale, std::abs(out[static_cast<size_t>(P + j)]));
        ddscale = std::max(ddscale, std::abs(out[static_cast<size_t>(2 * P + j)]));
      }
      EXPECT_NEAR(sum, 1.0, 1e-14) << "p=" << p << " u=" << u;
      EXPECT_NEAR(dsum, 0.0, 1e-13 * std::max(1.0, dscale)) << "p=" << p << " u=" << u;
      EXPECT_NEAR(ddsum, 0.0, 1e-13 * std::max(1.0, ddscale)) << "p=" << p << " u=" << u;
    }
  }
}

TEST(BsplineBasis, DerivativesMatchCentralDifferences) {
  const double h = 1e-6;
  for (int p : {2, 3, 4}) {
    const KnotVector kv = p == 2 ? KnotVector({0, 0, 0, 0.2, 0.5, 0.5, 0.7, 1, 1, 1}, 2)
                                 : KnotVector::open_uniform(p, 5, 1.0, 3.0);
    const int P = p + 1;
    for (double u : samples_away_from_knots(kv, 7, 10 * h)) {
      int span = -1;
      const std::vector<double> at = eval(kv, u, 2, &span);
      std::vector<double> plus(static_cast<size_t>(3 * P)), minus(static_cast<size_t>(3 * P));
      bspline_basis_derivs(kv, span, u + h, 2, plus.data());  // same span: u +- h stays inside it
      bspline_basis_derivs(kv, span, u - h, 2, minus.data());
      double scale1 = 0, scale2 = 0;
      for (int j = 0; j < P; ++j) {
        scale1 = std::max(scale1, std::abs(at[static_cast<size_t>(P + j)]));
        scale2 = std::max(scale2, std::abs(at[static_cast<size_t>(2 * P + j)]));
      }
      for (int j = 0; j < P; ++j) {
        const double fd1 = (plus[static_cast<size_t>(j)] - minus[static_cast<size_t>(j)]) / (2 * h);
        const double fd2 = (plus[static_cast<size_t>(P + j)] - minus[static_cast<size_t>(P + j)]) / (2 * h);
        EXPECT_NEAR(at[static_cast<size_t>(P + j)], fd1, 1e-6 * scale1) << "p=" << p << " u=" << u;
        EXPECT_NEAR(at[static_cast<size_t>(2 * P + j)], fd2, 1e-6 * scale2) << "p=" << p << " u=" << u;
      }
    }
  }
}

TEST(BsplineBasis, HighDegreeUsesHeapPathCorrectly) {
  for (int p : {9, 10}) {
    const KnotVector kv = KnotVector::open_uniform(p, 4);
    const int P = p + 1;
    for (int s = 0; s <= 100; ++s) {
      const double u = s / 100.0;
      int span = -1;
      const std::vector<double> out = eval(kv, u, 2, &span);
      double sum = 0;
      for (int j = 0; j < P; ++j) {
        EXPECT_GE(out[static_cast<size_t>(j)], 0.0);
        sum += out[static_cast<size_t>(j)];
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      // Spot-check against the recursive reference at a few points (it is exponential in p).
      if (s % 25 == 13) {
        for (int j = 0; j < P; ++j) {
          for (int k = 0; k <= 1; ++k) {
            const double ref = ref_deriv(kv.knots(), span - p + j, p, k, u, kv.domain_end());
            EXPECT_NEAR(out[static_cast<size_t>(k * P + j)], ref, 1e-11 * std::max(1.0, std::abs(ref)));
          }
        }
      }
    }
  }
}

TEST(BsplineBasis, Degree10Bernstein) {
  // On a single Bezier span the basis is Bernstein: N_j(u) = C(10, j) u^j (1-u)^(10-j).
  const KnotVector kv = KnotVector::open_uniform(10, 1);
  const double u = 0.3;
  const std::vector<double> out = eval(kv, u, 0);
  double binom = 1.0;
  for (int j = 0; j <= 10; ++j) {
    const double expected = binom * std::pow(u, j) * std::pow(1 - u, 10 - j);
    EXPECT_NEAR(out[static_cast<size_t>(j)], expected, 1e-15);
    binom = binom * (10 - j) / (j + 1);
  }
}

TEST(BsplineBasis, LinearDegreeHasNoSecondDerivative) {
  const KnotVector kv = KnotVector::open_uniform(1, 4);
  const std::vector<double> out = eval(kv, 0.3, 3);
  // span 3 ([0.25, 0.5)): hats 1 - 4(u-0.25) = 0.8 and 4(u-0.25) = 0.2, slopes -4 and 4.
  EXPECT_NEAR(out[0], 0.8, 1e-15);
  EXPECT_NEAR(out[1], 0.2, 1e-15);
  EXPECT_NEAR(out[2], -4.0, 1e-14);
  EXPECT_NEAR(out[3], 4.0, 1e-14);
  for (size_t k = 4; k < out.size(); ++k) EXPECT_EQ(out[k], 0.0);
}

TEST(BsplineBasisValidation, BadSpanAndDerivativeOrder) {
  const KnotVector kv({0, 0, 0, 1, 1, 2, 2, 2}, 2);
  double out[9];
  try {
    bspline_basis_derivs(kv, 3, 1.0, 0, out);  // [knots[3], knots[4]) = [1, 1) is empty
    ADD_FAILURE() << "expected NurbsError";
  } catch (const NurbsError& e) {
    EXPECT_THAT(e.what(), HasSubstr("knot span 3 is not a non-empty span"));
  }
  EXPECT_THROW(bspline_basis_derivs(kv, 1, 0.5, 0, out), NurbsError);
  EXPECT_THROW(bspline_basis_derivs(kv, 5, 0.5, 0, out), NurbsError);
  try {
    bspline_basis_derivs(kv, 0.5, -1, out);
    ADD_FAILURE() << "expected NurbsError";
  } catch (const NurbsError& e) {
    EXPECT_THAT(e.what(), HasSubstr("derivative order must be >= 0, got -1"));
  }
  EXPECT_THROW(bspline_basis_derivs(kv, 2.5, 0, out), NurbsError);  // outside the domain [0, 2]
}

}  // namespace
}  // namespace shellfrac::nurbs
