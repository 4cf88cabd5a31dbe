// MLS shape functions near cracks (thesis sec. 4.6): polynomial reproduction, exact derivatives, support
// selection around a slit and failure reporting. The cross-check against an independent Ceres fit is in
// mls_basis_ceres_test.cpp.
#include "shell/mls_basis.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <utility>

#include "nurbs/patch_builders.hpp"
#include "tests/shell/mls_test_grids.hpp"

namespace shellfrac::shell {
namespace {

using test::quadratic_grid;
using test::slit_visible;

constexpr double kPi = 3.14159265358979323846;

// A quadratic f = c . p(y) in cell-scaled coordinates y = (xi - origin) / (l_u, l_v), so that data vary by
// O(1) across a support of a few cells and errors measured in cell units are meaningful on any grid.
struct Quadratic {
  std::array<double, 6> c{};
  Eigen::Vector2d origin = Eigen::Vector2d::Zero(), scale = Eigen::Vector2d::Ones();
  Eigen::Vector2d local(const Eigen::Vector2d& x) const { return (x - origin).cwiseQuotient(scale); }
  double value(const Eigen::Vector2d& x) const {
    const Eigen::Vector2d y = local(x);
    return c[0] + c[1] * y.x() + c[2] * y.y() + c[3] * y.x() * y.x() + c[4] * y.x() * y.y() + c[5] * y.y() * y.y();
  }
  // Derivatives with respect to the cell-scaled coordinates (= l_a d/dxi_a).
  double d1(const Eigen::Vector2d& x) const { return c[1] + 2.0 * c[3] * local(x).x() + c[4] * local(x).y(); }
  double d2(const Eigen::Vector2d& x) const { return c[2] + c[4] * local(x).x() + 2.0 * c[5] * local(x).y(); }
  double d11() const { return 2.0 * c[3]; }
  double d12() const { return c[4]; }
  double d22() const { return 2.0 * c[5]; }
};

// Random coefficients in [-1, 1], origin within a cell of xi.
Quadratic random_quadratic(std::mt19937& rng, const Eigen::Vector2d& xi, double l_u, double l_v) {
  std::uniform_real_distribution<double> coef(-1.0, 1.0);
  Quadratic q;
  for (double& c : q.c) c = coef(rng);
  q.scale = Eigen::Vector2d(l_u, l_v);
  q.origin = xi + Eigen::Vector2d(coef(rng) * l_u, coef(rng) * l_v);
  return q;
}


// A strongly non-uniform grid: spacing varies by a factor ~3 across the patch; cell size = mean spacing.
ControlGrid graded_grid(int n_u, int n_v) {
  ControlGrid g;
  auto graded = [](int n) {
    std::vector<double> x(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / (n - 1);
      x[static_cast<std::size_t>(i)] = 0.5 * t + 0.5 * t * t;  // spacing grows from 0.5/(n-1) to 1.5/(n-1)
    }
    return x;
  };
  g.u = graded(n_u);
  g.v = graded(n_v);
  g.cell_u = 1.0 / (n_u - 1);
  g.cell_v = 1.0 / (n_v - 1);
  return g;
}

// Sum_k R_k f(xi_k) and its derivatives.
template <class Candidates>
std::array<double, 6> interpolate(const MlsBasis& b, const Candidates& cands, const Quadratic& f) {
  std::array<double, 6> s{};
  for (int k = 0; k < b.size(); ++k) {
    const double u = f.value(cands.point(b.index[static_cast<std::size_t>(k)]));
    s[0] += b.R[static_cast<std::size_t>(k)] * u;
    s[1] += b.R1[static_cast<std::size_t>(k)] * u;
    s[2] += b.R2[static_cast<std::size_t>(k)] * u;
    s[3] += b.R11[static_cast<std::size_t>(k)] * u;
    s[4] += b.R12[static_cast<std::size_t>(k)] * u;
    s[5] += b.R22[static_cast<std::size_t>(k)] * u;
  }
  return s;
}

// Reproduction errors in cell units: |sum R f - f|, l_a |sum R_a f - f_a|, l_a l_b |sum R_ab f - f_ab|.
struct ReproductionError {
  double value = 0.0, first = 0.0, second = 0.0;
  void merge(const ReproductionError& o) {
    value = std::max(value, o.value);
    first = std::max(first, o.first);
    second = std::max(second, o.second);
  }
};

template <class Candidates>
ReproductionError reproduction_error(const Eigen::Vector2d& xi, const Candidates& cands, const MlsBasis& b,
                                     const Quadratic& f) {
  const std::array<double, 6> s = interpolate(b, cands, f);
  const double lu = f.scale.x(), lv = f.scale.y();
  ReproductionError e;
  e.value = std::abs(s[0] - f.value(xi));
  e.first = std::max(std::abs(s[1] * lu - f.d1(xi)), std::abs(s[2] * lv - f.d2(xi)));
  e.second = std::max({std::abs(s[3] * lu * lu - f.d11()), std::abs(s[4] * lu * lv - f.d12()),
                       std::abs(s[5] * lv * lv - f.d22())});
  return e;
}

// Default tolerances (cell units): 1e-10 for values and first derivatives, 1e-9 for second derivatives
// (the default min_rcond = 1e-3 bounds them near 3e-10, see docs/mls.md; 1e-10 needs min_rcond >= 3e-3).
template <class Candidates>
ReproductionError expect_quadratic_reproduction(const Eigen::Vector2d& xi, const Candidates& cands,
                                                const MlsBasis& b, const Quadratic& f, double tol_second = 1e-9) {
  const ReproductionError e = reproduction_error(xi, cands, b, f);
  EXPECT_LT(e.value, 1e-10) << "at " << xi.transpose();
  EXPECT_LT(e.first, 1e-10) << "at " << xi.transpose();
  EXPECT_LT(e.second, tol_second) << "at " << xi.transpose();
  return e;
}


TEST(MlsWeight, CubicSplineIsC2AndMatchesCorrectedEq418) {
  // thesis Eq. 4.18 with the corrected second branch: both sides give 1/6, -1, 4 at r = 1/2.
  const CubicWeight lo = cubic_weight(0.5), hi = cubic_weight(std::nextafter(0.5, 1.0));
  EXPECT_NEAR(lo.w, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(hi.w, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(lo.dw, -1.0, 1e-14);
  EXPECT_NEAR(hi.dw, -1.0, 1e-14);
  EXPECT_NEAR(lo.ddw, 4.0, 1e-14);
  EXPECT_NEAR(hi.ddw, 4.0, 1e-14);
  EXPECT_NEAR(cubic_weight(0.0).w, 2.0 / 3.0, 1e-15);
  const CubicWeight one = cubic_weight(std::nextafter(1.0, 0.0));
  EXPECT_NEAR(one.w, 0.0, 1e-15);
  EXPECT_NEAR(one.dw, 0.0, 1e-14);
  EXPECT_NEAR(one.ddw, 0.0, 1e-14);
  EXPECT_EQ(cubic_weight(1.0).w, 0.0);
  for (double r : {0.1, 0.3, 0.7, 0.9}) {  // second branch as the literal polynomial
    if (r > 0.5) {
      EXPECT_NEAR(cubic_weight(r).w, 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r, 1e-15);
    } else {
      EXPECT_NEAR(cubic_weight(r).w, 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r, 1e-15);
    }
  }
}

TEST(MlsBasis, ReproducesQuadraticsWithDerivativesOnGrevilleGrids) {
  struct Case {
    const char* name;
    ControlGrid grid;
  };
  const std::vector<Case> cases = {{"quadratic 10x7", quadratic_grid(10, 7)},
                                   {"quadratic 100x100 (l = 0.01)", quadratic_grid(100, 100)},
                                   {"graded 13x9", graded_grid(13, 9)}};
  MlsSettings strict;  // 1e-2 is unreachable at some graded-grid corners (rcond 7e-3 at 4.5 l)
  strict.min_rcond = 3e-3;
  for (const MlsSettings& settings : {MlsSettings{}, strict}) {
    const double tol_second = settings.min_rcond >= 3e-3 ? 1e-10 : 1e-9;
    for (const Case& c : cases) {
      std::mt19937 rng(7);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      MlsBasis b;
      ReproductionError worst;
      for (int trial = 0; trial < 1000; ++trial) {
        // Every fourth point sits within one cell of the border, where the Greville spacing halves.
        Eigen::Vector2d xi(unit(rng), unit(rng));
        if (trial % 4 == 0) xi.x() = unit(rng) * c.grid.cell_u;
        if (trial % 4 == 1) xi.y() = 1.0 - unit(rng) * c.grid.cell_v;
        if (trial % 8 == 2) xi = Eigen::Vector2d(0.0, 1.0);  // corner
        ASSERT_TRUE(mls_basis(xi, c.grid, AlwaysVisible{}, settings, b))
            << c.name << ", min_rcond " << settings.min_rcond << ": " << b.reason;
        EXPECT_GE(b.size(), 9);
        const Quadratic f = random_quadratic(rng, xi, c.grid.cell_u, c.grid.cell_v);
        worst.merge(expect_quadratic_reproduction(xi, c.grid, b, f, tol_second));
      }
      std::printf("[ quadratic reproduction, min_rcond %g ] %-30s worst error in cell units: value %.1e, "
                  "first %.1e, second %.1e\n",
                  settings.min_rcond, c.name, worst.value, worst.first, worst.second);
    }
  }
}

TEST(MlsBasis, UnitSquareSupportMatchesThesisNurbsEquivalent) {
  // Interior point of a uniform grid: at d = 1.5 l the open box holds exactly the 3x3 nearest points.
  const ControlGrid grid = quadratic_grid(20, 20);
  MlsBasis b;
  ASSERT_TRUE(mls_basis(Eigen::Vector2d(0.512, 0.437), grid, AlwaysVisible{}, MlsSettings{}, b)) << b.reason;
  EXPECT_EQ(b.size(), 9);
  EXPECT_DOUBLE_EQ(b.factor, 1.5);
  EXPECT_GT(b.rcond, 1e-4);
  // A cell midpoint sees only 2x2 points at 1.5 l (the +-1.5 l neighbours have weight 0): it must grow.
  ASSERT_TRUE(mls_basis(Eigen::Vector2d(0.5, 0.5), grid, AlwaysVisible{}, MlsSettings{}, b)) << b.reason;
  EXPECT_GT(b.factor, 1.5);
  EXPECT_GE(b.size(), 9);
}

TEST(MlsBasis, PartitionOfUnity) {
  // sum R = 1 to 1e-12. The derivative sums are measured in cell units (l_a sum R_a, l_a l_b sum R_ab);
  // their round-off floor grows with the conditioning of the support (see the reproduction test):
  // asserted to 1e-11 (first) and 2e-10 (second) with the default settings.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const ControlGrid grid = quadratic_grid(12, 9);
  MlsBasis b;
  double worst0 = 0.0, worst1 = 0.0, worst2 = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector2d xi(unit(rng), unit(rng));
    ASSERT_TRUE(mls_basis(xi, grid, AlwaysVisible{}, MlsSettings{}, b)) << b.reason;
    double s = 0, s1 = 0, s2 = 0, s11 = 0, s12 = 0, s22 = 0;
    for (int k = 0; k < b.size(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      s += b.R[i];
      s1 += b.R1[i];
      s2 += b.R2[i];
      s11 += b.R11[i];
      s12 += b.R12[i];
      s22 += b.R22[i];
    }
    const double lu = grid.cell_u, lv = grid.cell_v;
    const double e0 = std::abs(s - 1.0);
    const double e1 = std::max(std::abs(s1 * lu), std::abs(s2 * lv));
    const double e2 = std::max({std::abs(s11 * lu * lu), std::abs(s12 * lu * lv), std::abs(s22 * lv * lv)});
    EXPECT_LT(e0, 1e-12);
    EXPECT_LT(e1, 1e-11);
    EXPECT_LT(e2, 2e-10);
    worst0 = std::max(worst0, e0);
    worst1 = std::max(worst1, e1);
    worst2 = std::max(worst2, e2);
  }
  std::printf("[ partition of unity ] worst |sum R - 1| = %.1e, l |sum dR| = %.1e, l^2 |sum ddR| = %.1e\n", worst0,
              worst1, worst2);
}

// Map control point index -> value of one output array.
std::map<int, double> by_index(const MlsBasis& b, const std::vector<double>& values) {
  std::map<int, double> m;
  for (int k = 0; k < b.size(); ++k) m[b.index[static_cast<std::size_t>(k)]] = values[static_cast<std::size_t>(k)];
  return m;
}

double at(const std::map<int, double>& m, int k) {
  const auto it = m.find(k);
  return it == m.end() ? 0.0 : it->second;
}

// Central differences of R, R_1, R_2 along `step`, per control point index.
template <class Visible>
std::map<int, std::array<double, 3>> central_differences(const ControlGrid& grid, const Eigen::Vector2d& xi,
                                                         const Eigen::Vector2d& step, Visible visible, double factor) {
  MlsBasis bp, bm;
  EXPECT_TRUE(mls_basis(Eigen::Vector2d(xi + step), grid, visible, MlsSettings{}, bp)) << bp.reason;
  EXPECT_TRUE(mls_basis(Eigen::Vector2d(xi - step), grid, visible, MlsSettings{}, bm)) << bm.reason;
  std::map<int, std::array<double, 3>> out;
  // The basis jumps where the support factor changes (growth is discrete): no derivative there.
  if (bp.factor != factor || bm.factor != factor) return out;
  const double h = 2.0 * step.norm();
  for (int k = 0; k < bp.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    auto& d = out[bp.index[i]];
    d[0] += bp.R[i] / h;
    d[1] += bp.R1[i] / h;
    d[2] += bp.R2[i] / h;
  }
  for (int k = 0; k < bm.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    auto& d = out[bm.index[i]];
    d[0] -= bm.R[i] / h;
    d[1] -= bm.R1[i] / h;
    d[2] -= bm.R2[i] / h;
  }
  return out;
}

template <class Visible>
void check_against_finite_differences(const ControlGrid& grid, const Eigen::Vector2d& xi, Visible visible,
                                      double& worst1, double& worst2, int& skipped) {
  // Richardson-extrapolated central differences (4 D(h/2) - D(h)) / 3 with h = 1e-3 l, in cell units:
  // the h^2 term is cancelled (it is large where a support row has a tiny weight, l^4 |R''''| ~ 1e4), the
  // h^4 term is < 1e-9, and round-off is ~ 1e-12 / 1e-3 = 1e-9. Tolerance: 1e-6 on l R_a and l^2 R_ab.
  MlsBasis b;
  ASSERT_TRUE(mls_basis(xi, grid, visible, MlsSettings{}, b)) << b.reason;
  const std::array<double, 2> cell = {grid.cell_u, grid.cell_v};
  for (int a = 0; a < 2; ++a) {
    const double la = cell[static_cast<std::size_t>(a)];
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    step[a] = 1e-3 * la;
    // The weight is only C^2: its third derivative jumps at r = 0, 1/2 (and 1), where differences of R_a are
    // first-order accurate only. Skip stencils that straddle such a knot of any support point's weight.
    bool straddles = false;
    for (int id : b.index) {
      const double r = std::abs(grid.point(id)[a] - xi[a]) / (b.factor * la);
      for (double knot : {0.0, 0.5, 1.0}) straddles |= std::abs(r - knot) < 2e-3 / b.factor;
    }
    if (straddles) {
      ++skipped;
      continue;
    }
    const auto big = central_differences(grid, xi, step, visible, b.factor);
    const auto small = central_differences(grid, xi, Eigen::Vector2d(0.5 * step), visible, b.factor);
    if (big.empty() || small.empty()) {
      ++skipped;
      continue;
    }
    for (int k = 0; k < b.size(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      const int id = b.index[i];
      std::array<double, 3> fd{};
      for (std::size_t c = 0; c < 3; ++c) fd[c] = (4.0 * small.at(id)[c] - big.at(id)[c]) / 3.0;
      const double exact = a == 0 ? b.R1[i] : b.R2[i];
      const double exact_a1 = a == 0 ? b.R11[i] : b.R12[i];  // d/dxi_a of R_1
      const double exact_a2 = a == 0 ? b.R12[i] : b.R22[i];  // d/dxi_a of R_2
      const double e1 = std::abs(fd[0] - exact) * la;
      const double e2 =
          std::max(std::abs(fd[1] - exact_a1) * grid.cell_u, std::abs(fd[2] - exact_a2) * grid.cell_v) * la;
      EXPECT_LT(e1, 1e-6) << "R_" << a + 1 << " of point " << id << " at " << xi.transpose();
      EXPECT_LT(e2, 1e-6) << "second derivative along " << a + 1 << " of point " << id << " at " << xi.transpose();
      worst1 = std::max(worst1, e1);
      worst2 = std::max(worst2, e2);
    }
  }
}

TEST(MlsBasis, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.05, 0.95);
  const ControlGrid grid = quadratic_grid(10, 8);
  double worst1 = 0.0, worst2 = 0.0;
  int skipped = 0;
  for (int trial = 0; trial < 100; ++trial) {
    check_against_finite_differences(grid, Eigen::Vector2d(unit(rng), unit(rng)), AlwaysVisible{}, worst1, worst2,
                                     skipped);
  }
  // Also next to the slit, where the support is enlarged and one-sided.
  for (double v : {0.12, 0.27, 0.41}) {
    check_against_finite_differences(grid, Eigen::Vector2d(0.47, v), slit_visible, worst1, worst2, skipped);
    check_against_finite_differences(grid, Eigen::Vector2d(0.53, v), slit_visible, worst1, worst2, skipped);
  }
  EXPECT_LT(skipped, 20) << "too many stencils straddle a support-factor change or a weight knot";
  std::printf("[ finite differences ] worst |l dR - FD| = %.2e, |l^2 ddR - FD| = %.2e (tolerance 1e-6); %d of 212 "
              "stencils straddled a support-factor change or a weight knot and were skipped\n",
              worst1, worst2, skipped);
}

TEST(MlsBasis, FlatPatchMatchesNurbsSurfaceExactly) {
  // Positions are an affine map of the Greville points, which both NURBS and MLS (quadratic
  // completeness) reproduce exactly: positions and tangents agree to round-off.
  nurbs::Frame frame;
  frame.origin = nurbs::Vec3(0.3, -1.0, 2.0);
  frame.axis_u = nurbs::Vec3(1.0, 2.0, 2.0).normalized();
  frame.axis_v = frame.axis_u.cross(nurbs::Vec3(0.0, 0.0, 1.0)).normalized();
  const nurbs::NurbsSurface surface = nurbs::flat_patch(2.0, 1.5, 9, 7, frame);
  const ControlGrid grid = ControlGrid::from_surface(surface);
  ASSERT_EQ(grid.size(), static_cast<int>(surface.control_points().size()));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MlsBasis b;
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector2d xi(unit(rng), unit(rng));
    ASSERT_TRUE(mls_basis(xi, grid, AlwaysVisible{}, MlsSettings{}, b)) << b.reason;
    nurbs::Vec3 x = nurbs::Vec3::Zero(), du = x, dv = x, duu = x, duv = x, dvv = x;
    for (int k = 0; k < b.size(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      const nurbs::Vec3& P = surface.control_points()[static_cast<std::size_t>(b.index[i])];
      x += b.R[i] * P;
      du += b.R1[i] * P;
      dv += b.R2[i] * P;
      duu += b.R11[i] * P;
      duv += b.R12[i] * P;
      dvv += b.R22[i] * P;
    }
    const nurbs::SurfacePoint s = surface.evaluate(xi.x(), xi.y());
    worst = std::max({worst, (x - s.x).norm(), (du - s.du).norm(), (dv - s.dv).norm()});
    EXPECT_LT((x - s.x).norm(), 1e-8);
    EXPECT_LT((du - s.du).norm(), 1e-8);
    EXPECT_LT((dv - s.dv).norm(), 1e-8);
    // Flat: zero second derivatives, up to the ~1e-10 cell-unit reproduction error times |P| / l^2 (~1e2).
    EXPECT_LT(duu.norm() + duv.norm() + dvv.norm(), 1e-7);
  }
  std::printf("[ flat patch ] worst |MLS - NURBS| (position, tangents) = %.2e\n", worst);
}

TEST(MlsBasis, CylinderDeviationFromNurbsIsSecondOrderInCellSize) {
  // On a curved patch MLS interpolates the control net, which lies off the surface: a quadratic
  // B-spline control point sits about |S_uu| l^2 / 8 from its Greville point's surface point (the
  // B-spline reproduces quadratics, and sum_i N_i (t*_i - t)^2 <= l^2 / 4 for uniform knots). Here
  // S_uu ~ R theta^2 (radius 1, sweep theta = pi/2), so the position gap is bounded by
  // R theta^2 l^2 / 4 and a tangent gap of order that bound / l. Halving l must roughly quarter the gap.
  const double radius = 1.0, theta = 0.5 * kPi;
  std::array<double, 2> gap_x{}, gap_t{};
  for (int level = 0; level < 2; ++level) {
    const int cells = 16 << level;
    const nurbs::NurbsSurface surface = nurbs::cylinder_segment(radius, 1.0, theta, cells, cells);
    const ControlGrid grid = ControlGrid::from_surface(surface);
    MlsBasis b;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int trial = 0; trial < 400; ++trial) {
      const Eigen::Vector2d xi(unit(rng), unit(rng));
      ASSERT_TRUE(mls_basis(xi, grid, AlwaysVisible{}, MlsSettings{}, b)) << b.reason;
      nurbs::Vec3 x = nurbs::Vec3::Zero(), du = x, dv = x;
      for (int k = 0; k < b.size(); ++k) {
        const auto i = static_cast<std::size_t>(k);
        const nurbs::Vec3& P = surface.control_points()[static_cast<std::size_t>(b.index[i])];
        x += b.R[i] * P;
        du += b.R1[i] * P;
        dv += b.R2[i] * P;
      }
      const nurbs::SurfacePoint s = surface.evaluate(xi.x(), xi.y());
      gap_x[static_cast<std::size_t>(level)] = std::max(gap_x[static_cast<std::size_t>(level)], (x - s.x).norm());
      gap_t[static_cast<std::size_t>(level)] =
          std::max(gap_t[static_cast<std::size_t>(level)], std::max((du - s.du).norm() / s.du.norm(),
                                                                    (dv - s.dv).norm() / s.dv.norm()));
    }
    const double l = 1.0 / cells;
    const double bound = radius * theta * theta * l * l / 4.0;
    std::printf("[ cylinder r=1 sweep=90deg, %2d cells ] max |x_MLS - x_NURBS| = %.3e (bound %.3e), "
                "max relative tangent gap = %.3e\n",
                cells, gap_x[static_cast<std::size_t>(level)], bound, gap_t[static_cast<std::size_t>(level)]);
    EXPECT_LT(gap_x[static_cast<std::size_t>(level)], bound);
    EXPECT_LT(gap_t[static_cast<std::size_t>(level)], theta * theta * l);  // O(l) relative tangent error
  }
  EXPECT_LT(gap_x[1], 0.35 * gap_x[0]);  // second order: ~1/4 when l halves
}

TEST(MlsBasis, SlitSupportStaysOnOneSideAndGrows) {
  const ControlGrid grid = quadratic_grid(10, 10);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MlsBasis b;
  int grown = 0, checked = 0;
  ReproductionError worst;
  for (int trial = 0; trial < 200; ++trial) {
    // Within 0.08 of the slit, below its tip.
    const double side = trial % 2 == 0 ? -1.0 : 1.0;
    const Eigen::Vector2d xi(0.5 + side * (0.005 + 0.075 * unit(rng)), 0.02 + 0.46 * unit(rng));
    std::set<std::pair<double, double>> asked;  // visibility is asked at most once per candidate
    int calls = 0;
    auto visible = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& c) {
      ++calls;
      EXPECT_EQ(a, xi);
      EXPECT_TRUE(asked.insert({c.x(), c.y()}).second) << "visibility asked twice for " << c.transpose();
      return slit_visible(a, c);
    };
    ASSERT_TRUE(mls_basis(xi, grid, visible, MlsSettings{}, b)) << b.reason;
    EXPECT_GE(b.size(), 9);
    EXPECT_GT(b.factor, 1.5);
    EXPECT_LE(b.factor, 4.5);
    grown += b.factor > 1.5;
    for (int id : b.index) {
      const Eigen::Vector2d p = grid.point(id);
      EXPECT_TRUE(slit_visible(xi, p)) << "support point " << p.transpose() << " hidden from " << xi.transpose();
      if (xi.y() < 0.3) {  // away from the tip no segment can reach around it
        EXPECT_GT((p.x() - 0.5) * side, 0.0) << "point " << p.transpose() << " across the slit from "
                                             << xi.transpose();
        ++checked;
      }
    }
    worst.merge(expect_quadratic_reproduction(xi, grid, b, random_quadratic(rng, xi, grid.cell_u, grid.cell_v)));
  }
  std::printf("[ slit ] worst reproduction error in cell units: value %.1e, first %.1e, second %.1e\n",
              worst.value, worst.first, worst.second);
  EXPECT_EQ(grown, 200);
  EXPECT_GT(checked, 1000);
}

TEST(MlsBasis, SlitPointsMayStillSeeAroundTheTip) {
  // Just below the tip the support reaches around it; shape functions stay valid and visible-only.
  const ControlGrid grid = quadratic_grid(10, 10);
  MlsBasis b;
  const Eigen::Vector2d xi(0.47, 0.46);
  ASSERT_TRUE(mls_basis(xi, grid, slit_visible, MlsSettings{}, b)) << b.reason;
  int across = 0;
  for (int id : b.index) {
    EXPECT_TRUE(slit_visible(xi, grid.point(id)));
    across += grid.point(id).x() > 0.5;
  }
  EXPECT_GT(across, 0);
  std::mt19937 rng(1);
  expect_quadratic_reproduction(xi, grid, b, random_quadratic(rng, xi, grid.cell_u, grid.cell_v));
}

void expect_clean_failure(const MlsBasis& b, MlsStatus status) {
  EXPECT_FALSE(b.ok);
  EXPECT_EQ(b.status, status);
  EXPECT_FALSE(b.reason.empty());
  EXPECT_TRUE(b.index.empty() && b.R.empty() && b.R1.empty() && b.R2.empty() && b.R11.empty() && b.R12.empty() &&
              b.R22.empty());
  EXPECT_TRUE(std::isfinite(b.factor));
  EXPECT_TRUE(std::isfinite(b.rcond));
  std::printf("[ failure ] %s\n", b.reason.c_str());
}

TEST(MlsBasis, CollinearControlPointsAreReportedNotInverted) {
  ControlPointList line;
  line.cell_u = line.cell_v = 0.1;
  for (int k = 0; k <= 20; ++k) {  // 21 points on the diagonal u = v
    line.u.push_back(0.05 * k);
    line.v.push_back(0.05 * k);
  }
  MlsBasis b;
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.5, 0.52), line, AlwaysVisible{}, MlsSettings{}, b));
  expect_clean_failure(b, MlsStatus::ill_conditioned);
  EXPECT_DOUBLE_EQ(b.factor, 4.5);

  // Nearly collinear: a 1e-9 l wobble is far below the conditioning threshold.
  ControlPointList wobble;
  wobble.cell_u = wobble.cell_v = 0.1;
  for (int k = 0; k <= 40; ++k) {
    wobble.u.push_back(0.025 * k);
    wobble.v.push_back(0.3 + (k % 2) * 1e-10);
  }
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.5, 0.3), wobble, AlwaysVisible{}, MlsSettings{}, b));
  expect_clean_failure(b, MlsStatus::ill_conditioned);
}

TEST(MlsBasis, TooFewVisibleControlPointsAreReported) {
  const ControlGrid grid = quadratic_grid(10, 10);
  MlsBasis b;
  // Only five control points, not collinear, are visible from anywhere: the 2x2 corner block and (0.15, 0.15).
  auto five = [&](const Eigen::Vector2d&, const Eigen::Vector2d& c) {
    return (c.x() < 0.1 && c.y() < 0.1) || (std::abs(c.x() - 0.15) < 1e-12 && std::abs(c.y() - 0.15) < 1e-12);
  };
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.2, 0.1), grid, five, MlsSettings{}, b));
  expect_clean_failure(b, MlsStatus::too_few_neighbours);
  // With min_neighbours lowered to 5, the five points still cannot carry 6 unknowns.
  MlsSettings loose;
  loose.min_neighbours = 5;
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.2, 0.1), grid, five, loose, b));
  EXPECT_FALSE(b.ok);
  EXPECT_TRUE(b.index.empty());
}

TEST(MlsBasis, LinearOrderReproducesLinearFieldsFromThreePointsNotInALine) {
  // The shell's linear fallback: the five points above carry the 3-term basis [1, u, v]. Values and
  // first derivatives of 1, u, v are reproduced to round-off, second derivatives of them vanish; the
  // quadratic u^2 is not reproduced (that is what the quadratic basis is for).
  const ControlGrid grid = quadratic_grid(10, 10);
  auto five = [&](const Eigen::Vector2d&, const Eigen::Vector2d& c) {
    return (c.x() < 0.1 && c.y() < 0.1) || (std::abs(c.x() - 0.15) < 1e-12 && std::abs(c.y() - 0.15) < 1e-12);
  };
  MlsSettings linear;
  linear.order = 1;
  linear.min_neighbours = 3;
  const Eigen::Vector2d xi(0.2, 0.1);
  MlsBasis b;
  ASSERT_TRUE(mls_basis(xi, grid, five, linear, b)) << b.reason;
  EXPECT_EQ(b.size(), 5);
  double s = 0, s1 = 0, s2 = 0, u2 = 0;
  Eigen::Vector2d x = Eigen::Vector2d::Zero(), x1 = x, x2 = x, x11 = x, x12 = x, x22 = x;
  for (int k = 0; k < b.size(); ++k) {
    const Eigen::Vector2d c = grid.point(b.index[static_cast<size_t>(k)]);
    const auto K = static_cast<size_t>(k);
    s += b.R[K];
    s1 += b.R1[K];
    s2 += b.R2[K];
    x += b.R[K] * c;
    x1 += b.R1[K] * c;
    x2 += b.R2[K] * c;
    x11 += b.R11[K] * c;
    x12 += b.R12[K] * c;
    x22 += b.R22[K] * c;
    u2 += b.R[K] * c.x() * c.x();
  }
  const double l = 0.1;
  EXPECT_NEAR(s, 1.0, 1e-13);
  EXPECT_NEAR(s1 * l, 0.0, 1e-12);
  EXPECT_NEAR(s2 * l, 0.0, 1e-12);
  EXPECT_LE((x - xi).norm() / l, 1e-12);
  EXPECT_LE((x1 - Eigen::Vector2d(1, 0)).norm(), 1e-12);
  EXPECT_LE((x2 - Eigen::Vector2d(0, 1)).norm(), 1e-12);
  EXPECT_LE((x11.norm() + x12.norm() + x22.norm()) * l, 1e-11);
  EXPECT_GT(std::abs(u2 - xi.x() * xi.x()) / (l * l), 1e-3);
  // Three points in a line cannot fix a plane: reported, not inverted.
  ControlPointList line;
  line.cell_u = line.cell_v = 0.1;
  for (int k = 0; k < 3; ++k) {
    line.u.push_back(0.45 + 0.05 * k);
    line.v.push_back(0.5);
  }
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.5, 0.52), line, AlwaysVisible{}, linear, b));
  expect_clean_failure(b, MlsStatus::ill_conditioned);
}

TEST(MlsBasis, InvalidInputIsReported) {
  const ControlGrid grid = quadratic_grid(4, 4);
  MlsBasis b;
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(std::nan(""), 0.5), grid, AlwaysVisible{}, MlsSettings{}, b));
  expect_clean_failure(b, MlsStatus::invalid_input);
  MlsSettings bad;
  bad.growth = 1.0;
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.5, 0.5), grid, AlwaysVisible{}, bad, b));
  expect_clean_failure(b, MlsStatus::invalid_input);
  ControlGrid flat = grid;
  flat.cell_v = 0.0;
  EXPECT_FALSE(mls_basis(Eigen::Vector2d(0.5, 0.5), flat, AlwaysVisible{}, MlsSettings{}, b));
  expect_clean_failure(b, MlsStatus::invalid_input);
}

TEST(MlsBasis, PlainListAndGridGiveTheSameBasis) {
  const ControlGrid grid = quadratic_grid(8, 6);
  ControlPointList list;
  list.cell_u = grid.cell_u;
  list.cell_v = grid.cell_v;
  for (int k = 0; k < grid.size(); ++k) {
    list.u.push_back(grid.point(k).x());
    list.v.push_back(grid.point(k).y());
  }
  MlsBasis a, b;
  const Eigen::Vector2d xi(0.46, 0.3);
  ASSERT_TRUE(mls_basis(xi, grid, slit_visible, MlsSettings{}, a));
  ASSERT_TRUE(mls_basis(xi, list, slit_visible, MlsSettings{}, b));
  ASSERT_EQ(a.size(), b.size());
  const auto rb = by_index(b, b.R), r11b = by_index(b, b.R11);
  for (int k = 0; k < a.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_NEAR(a.R[i], at(rb, a.index[i]), 1e-14);
    EXPECT_NEAR(a.R11[i], at(r11b, a.index[i]), 1e-9);
  }
}

// ---- Independent weighted least-squares fit with Ceres -------------------------------------------

}  // namespace
}  // namespace shellfrac::shell
