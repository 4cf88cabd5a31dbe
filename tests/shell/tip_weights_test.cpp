// Diffraction weights near a crack tip (shell/mls_basis.hpp TipWeights, docs/mls.md "Tip weights"): on a
// straight crack that ends inside a flat patch, the basis of the fallback chain is continuous past the
// tip and at it, keeps the two sides apart far from the tip, reproduces quadratics, and its derivatives
// match finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "nurbs/patch_builders.hpp"
#include "shell/basis_chain.hpp"

namespace shellfrac::shell {
namespace {

using Vec2 = Eigen::Vector2d;

// A unit flat patch of 10 x 10 quadratic cells (l = 0.1) cut from its left edge along v = 0.503 to a tip
// at u = 0.523 (off the control point rows and columns).
constexpr double kCell = 0.1;
const Vec2 kTip(0.523, 0.503);

struct TipScene {
  ControlGrid grid = ControlGrid::from_surface(nurbs::flat_patch(1.0, 1.0, 10, 10));
  crack2d::CrackGraph graph;
  crack2d::CrackIndex index;
  crack2d::CrackPortals portals;
  TipScene() : TipScene({Vec2(0.0, kTip.y()), kTip}) {}
  explicit TipScene(std::initializer_list<Vec2> polyline) {
    int prev = -1;
    for (const Vec2& p : polyline) {
      const int v = graph.add_vertex(p);
      if (prev >= 0) graph.add_edge(prev, v);
      prev = v;
    }
    index.rebuild(graph);
    portals.build(index, 1e-7 * kCell);
  }
  BasisChainSettings settings(TipWeights::Mode mode, double radius) const {
    BasisChainSettings s;
    s.mls.tip.mode = mode;
    s.mls.tip.radius = radius;
    return s;
  }
};

constexpr auto kDiffraction = TipWeights::Mode::diffraction;
constexpr auto kVisibility = TipWeights::Mode::visibility;

struct Eval {
  PointFit fit;
  double factor = 0.0;
  std::map<int, std::array<double, 6>> R;  // control point -> R, R1, R2, R11, R12, R22
};

Eval evaluate(const TipScene& s, const Vec2& xi, TipWeights::Mode mode, double radius = TipWeights{}.radius) {
  BasisChainWork work;
  Eval e;
  e.fit = fit_point_basis(xi, s.grid, s.index, s.portals, s.settings(mode, radius), work);
  const MlsBasis& b = work.basis;
  e.factor = b.factor;
  for (int k = 0; k < b.size(); ++k) {
    const auto i = static_cast<size_t>(k);
    e.R[b.index[i]] = {b.R[i], b.R1[i], b.R2[i], b.R11[i], b.R12[i], b.R22[i]};
  }
  return e;
}

// max_k |R_k(a) - R_k(b)| over the union of both supports (a missing point has R = 0).
double basis_jump(const Eval& a, const Eval& b) {
  double jump = 0.0;
  for (const auto& [k, r] : a.R) jump = std::max(jump, std::abs(r[0] - (b.R.count(k) ? b.R.at(k)[0] : 0.0)));
  for (const auto& [k, r] : b.R)
    if (!a.R.count(k)) jump = std::max(jump, std::abs(r[0]));
  return jump;
}

// Largest l^2 |R_ab| over the support: what the bending step bound sees (docs/fracture.md).
double largest_curvature_term(const Eval& e) {
  double m = 0.0;
  for (const auto& [k, r] : e.R) m = std::max({m, std::abs(r[3]), std::abs(r[4]), std::abs(r[5])});
  return m * kCell * kCell;
}

// A mode-I opening: control points above the crack's line move up by 1, those below down by 1 (out of
// plane), on top of a smooth bending. The surface value at xi is sum R_k z_k.
double opened_surface(const TipScene& s, const Eval& e) {
  double z = 0.0;
  for (const auto& [k, r] : e.R) {
    const Vec2 p = s.grid.point(k);
    z += r[0] * ((p.y() > kTip.y() ? 1.0 : -1.0) + 0.3 * std::sin(3.0 * p.x() + 2.0 * p.y()));
  }
  return z;
}

// Largest basis jump between neighbouring samples of a line crossing the crack's extension at u (past
// the tip), sampled every h in v over +-0.08; pairs whose support factor differs are skipped (the basis
// jumps where the discrete support growth changes, docs/mls.md).
double scan_past_tip(const TipScene& s, double u, double h, TipWeights::Mode mode) {
  double worst = 0.0;
  Eval prev = evaluate(s, Vec2(u, kTip.y() - 0.08), mode);
  for (double v = kTip.y() - 0.08 + h; v <= kTip.y() + 0.08; v += h) {
    Eval cur = evaluate(s, Vec2(u, v), mode);
    if (cur.factor == prev.factor && cur.fit.level == prev.fit.level) worst = std::max(worst, basis_jump(prev, cur));
    prev = std::move(cur);
  }
  return worst;
}

TEST(TipWeights, DiffractionBasisIsContinuousPastTheTip) {
  const TipScene s;
  for (double u : {kTip.x() + 0.027, kTip.x() + 0.077, kTip.x() + 0.177}) {
    const bool near_tip = u < kTip.x() + 0.1;  // farther on, the visibility basis has no jump in the scan either
    // A continuous basis: the largest jump between samples h apart shrinks with h (R_a l is O(1)).
    const double coarse = scan_past_tip(s, u, 1e-4, kDiffraction);
    const double fine = scan_past_tip(s, u, 1e-5, kDiffraction);
    const double visibility = scan_past_tip(s, u, 1e-5, kVisibility);
    std::printf("[ past the tip, u = %.3f ] largest basis jump: diffraction %.2e (h = 1e-4), %.2e (h = 1e-5); "
                "visibility %.2e (h = 1e-5)\n",
                u, coarse, fine, visibility);
    EXPECT_LT(fine, 2e-3);
    EXPECT_LT(fine, 0.2 * coarse + 1e-12);
    if (near_tip) {
      EXPECT_GT(visibility, 10.0 * fine);  // the defect diffraction removes
    }
  }
}

// Largest basis jump between neighbouring samples h apart on the segment from a to b (support factor or
// level changes skipped, as above).
double scan(const TipScene& s, const Vec2& a, const Vec2& b, double h, TipWeights::Mode mode) {
  const int n = static_cast<int>(std::ceil((b - a).norm() / h));
  double worst = 0.0;
  Eval prev = evaluate(s, a, mode);
  for (int i = 1; i <= n; ++i) {
    Eval cur = evaluate(s, a + (b - a) * (static_cast<double>(i) / n), mode);
    if (cur.factor == prev.factor && cur.fit.level == prev.fit.level) worst = std::max(worst, basis_jump(prev, cur));
    prev = std::move(cur);
  }
  return worst;
}

TEST(TipWeights, DiffractionBasisIsContinuousAroundTheOuterSideOfABend) {
  // The crack runs in from the left edge and bends down at kTip by about 60 degrees. On the outer
  // (upper) side of the bend the visibility rule hides the same side's control points beyond the bend
  // from points before it, and the basis jumps on every ray from such a control point past the corner.
  const TipScene s({Vec2(0.0, kTip.y()), kTip, Vec2(0.7, 0.2)});
  for (double u : {0.50, 0.51}) {
    const Vec2 a(u, kTip.y() + 0.004), b(u, kTip.y() + 0.1);
    const double coarse = scan(s, a, b, 1e-4, kDiffraction), fine = scan(s, a, b, 1e-5, kDiffraction);
    const double visibility = scan(s, a, b, 1e-5, kVisibility);
    std::printf("[ outer side of a bend, u = %.2f ] largest basis jump: diffraction %.2e (h = 1e-4), %.2e "
                "(h = 1e-5); visibility %.2e (h = 1e-5)\n",
                u, coarse, fine, visibility);
    EXPECT_LT(fine, 2e-3);
    EXPECT_LT(fine, 0.2 * coarse + 1e-12);
    EXPECT_GT(visibility, 10.0 * fine);
  }
  // Under the bend (its inner side) nothing changes: the corner has no portal there, and control points
  // across the crack stay out of the basis of a point 2 cells before the bend.
  const Vec2 xi(0.32, 0.49);
  const Eval e = evaluate(s, xi, kDiffraction);
  for (const auto& [k, r] : e.R) EXPECT_LT(s.grid.point(k).y(), kTip.y()) << "control point " << k;
}

TEST(TipWeights, DiffractionBasisClosesTheCrackAtTheTip) {
  const TipScene s;
  // Points on the two faces, a distance rho (cells) behind the tip at 60 degrees from the crack line.
  const double c = std::cos(M_PI / 3.0), sn = std::sin(M_PI / 3.0);
  double last = 1.0;
  for (double rho : {0.3, 0.1, 0.01, 1e-3, 1e-4}) {
    const Vec2 above = kTip + rho * kCell * Vec2(-c, sn), below = kTip + rho * kCell * Vec2(-c, -sn);
    const Eval a = evaluate(s, above, kDiffraction), b = evaluate(s, below, kDiffraction);
    const Eval va = evaluate(s, above, kVisibility), vb = evaluate(s, below, kVisibility);
    const double jump = basis_jump(a, b), opening = std::abs(opened_surface(s, a) - opened_surface(s, b));
    const double vis_opening = std::abs(opened_surface(s, va) - opened_surface(s, vb));
    const double curv = std::max(largest_curvature_term(a), largest_curvature_term(b));
    const double vis_curv = std::max(largest_curvature_term(va), largest_curvature_term(vb));
    // The published method (no fade): its second derivatives grow like 1 / rho.
    const double plain_curv = std::max(largest_curvature_term(evaluate(s, above, kDiffraction, 0.0)),
                                       largest_curvature_term(evaluate(s, below, kDiffraction, 0.0)));
    std::printf("[ at the tip, rho = %g cells ] without the fade: l^2 |R_ab| <= %.1f\n", rho, plain_curv);
    if (rho == 1e-4) {
      EXPECT_GT(plain_curv, 10.0 * vis_curv) << "the singularity the fade removes";
    }
    std::printf("[ at the tip, rho = %g cells ] diffraction: basis jump %.2e, opening %.2e, l^2 |R_ab| <= %.1f; "
                "visibility: opening %.2e, l^2 |R_ab| <= %.1f\n",
                rho, jump, opening, curv, vis_opening, vis_curv);
    // The fade chi keeps the second derivatives bounded as the point approaches the tip (no 1 / s2 growth).
    EXPECT_LT(curv, 3.0 * vis_curv + 10.0) << rho;
    if (rho <= 0.01) {
      EXPECT_LT(jump, 30.0 * rho) << rho;
      EXPECT_LT(opening, 30.0 * rho) << rho;
      EXPECT_LT(opening, last);
      EXPECT_GT(vis_opening, 0.5) << "the visibility rule keeps the faces apart up to the tip";
    }
    last = opening;
  }
}

TEST(TipWeights, FarFromTheTipTheSidesStayIndependent) {
  const TipScene s;
  // 3.7 cells behind the tip: nothing below the crack, as with the visibility rule.
  for (const Vec2& xi : {Vec2(0.15, 0.52), Vec2(0.2, 0.49), Vec2(0.3, 0.51)}) {
    const Eval e = evaluate(s, xi, kDiffraction);
    ASSERT_EQ(e.fit.level, BasisLevel::Quadratic);
    for (const auto& [k, r] : e.R)
      EXPECT_EQ(s.grid.point(k).y() > kTip.y(), xi.y() > kTip.y())
          << "control point " << k << " across the crack in the basis of " << xi.transpose();
  }
  // Half a cell behind the tip the hidden control points close to the tip take part with a weight, those
  // farther behind along the crack (1.5 cells and more) none; the visibility rule takes none of them.
  const Vec2 near(0.47, 0.52);
  const Eval d = evaluate(s, near, kDiffraction), v = evaluate(s, near, kVisibility);
  int around = 0;
  for (const auto& [k, r] : d.R) {
    const Vec2 p = s.grid.point(k);
    if (!s.index.crosses(near, p)) continue;
    ++around;
    EXPECT_GT(p.x(), kTip.x() - 0.15) << "control point " << k << " far along the crack has a weight";
  }
  EXPECT_GT(around, 0);
  for (const auto& [k, r] : v.R) EXPECT_FALSE(s.index.crosses(near, s.grid.point(k)));
}

// Quadratic fields and their derivatives, scaled to cells: f = sum c_i m_i((xi - o) / l).
double quad(const std::array<double, 6>& c, const Vec2& x, const Vec2& o, std::array<double, 6>& d) {
  const double a = (x.x() - o.x()) / kCell, b = (x.y() - o.y()) / kCell;
  d = {0, c[1] + 2 * c[3] * a + c[4] * b, c[2] + c[4] * a + 2 * c[5] * b, 2 * c[3], c[4], 2 * c[5]};
  return c[0] + c[1] * a + c[2] * b + c[3] * a * a + c[4] * a * b + c[5] * b * b;
}

TEST(TipWeights, DiffractionBasisIsAPartitionOfUnityAndReproducesQuadratics) {
  const TipScene s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> off(-2.0, 2.0), coef(-1.0, 1.0);
  double worst[3] = {0, 0, 0}, pu = 0.0;
  int with_tip = 0, tested = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec2 xi = kTip + kCell * Vec2(off(rng), off(rng));
    if (std::abs(xi.y() - kTip.y()) < 1e-6) continue;
    const Eval e = evaluate(s, xi, kDiffraction);
    if (e.fit.level != BasisLevel::Quadratic && e.fit.level != BasisLevel::RelaxedQuadratic) continue;
    ++tested;
    bool seen_around = false;
    for (const auto& [k, r] : e.R) seen_around |= s.index.crosses(e.fit.at, s.grid.point(k));
    with_tip += seen_around;
    std::array<double, 6> c{}, sum{}, dk{}, dx{};
    for (double& ci : c) ci = coef(rng);
    const Vec2 o = xi + kCell * Vec2(coef(rng), coef(rng));
    double one[3] = {0, 0, 0};
    for (const auto& [k, r] : e.R) {
      const double fk = quad(c, s.grid.point(k), o, dk);
      for (int j = 0; j < 6; ++j) sum[static_cast<size_t>(j)] += r[static_cast<size_t>(j)] * fk;
      one[0] += r[0];
      one[1] += r[1] * kCell;
      one[2] += r[2] * kCell;
    }
    const double f = quad(c, e.fit.at, o, dx);
    pu = std::max({pu, std::abs(one[0] - 1.0), std::abs(one[1]), std::abs(one[2])});
    worst[0] = std::max(worst[0], std::abs(sum[0] - f));
    worst[1] = std::max({worst[1], std::abs(sum[1] * kCell - dx[1]), std::abs(sum[2] * kCell - dx[2])});
    worst[2] = std::max({worst[2], std::abs(sum[3] * kCell * kCell - dx[3]), std::abs(sum[4] * kCell * kCell - dx[4]),
                         std::abs(sum[5] * kCell * kCell - dx[5])});
  }
  std::printf("[ diffraction reproduction ] %d quadratic fits, %d with control points seen around the tip: "
              "partition of unity %.1e, quadratic value %.1e, first %.1e, second %.1e (cell units)\n",
              tested, with_tip, pu, worst[0], worst[1], worst[2]);
  EXPECT_GT(with_tip, 50);
  EXPECT_LT(pu, 1e-11);
  EXPECT_LT(worst[0], 1e-10);
  EXPECT_LT(worst[1], 1e-10);
  EXPECT_LT(worst[2], 1e-9);
}

TEST(TipWeights, DiffractedWeightDerivativesMatchCentralDifferences) {
  // The weight alone, in support units: random control points, tips and evaluation points; stencils that
  // straddle a knot of the cubic spline (|f e_i| = 0, 1/2, 1) are skipped (the weight is C^2 only).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst1 = 0.0, worst2 = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 4000 && checked < 1000; ++trial) {
    const Vec2 y(0.0, 0.0), yk(unit(rng), unit(rng)), yc(0.6 * unit(rng), 0.6 * unit(rng));
    const double lambda = trial % 2 ? 1.0 : 2.0, eps = trial % 3 == 0 ? 0.0 : 0.05;
    auto W = [&](const Vec2& at) { return diffracted_weight(yk - at, at - yc, (yk - yc).norm(), lambda, eps); };
    const WeightDerivatives D = W(y);
    if (!(D.W > 0.0) || (y - yc).norm() < 0.02) continue;
    const double h = 1e-4;
    bool knot = false;
    for (const Vec2& p : {Vec2(h, 0), Vec2(-h, 0), Vec2(0, h), Vec2(0, -h), Vec2(0, 0)}) {
      const WeightDerivatives Dp = W(y + p);
      for (int i = 0; i < 2; ++i) {
        const double u = std::abs(Dp.stretch * (yk - y - p)[i]);
        for (double kn : {0.0, 0.5, 1.0}) knot |= std::abs(u - kn) < 1e-3;
      }
    }
    if (knot) continue;
    ++checked;
    for (int a = 0; a < 2; ++a) {
      Vec2 step = Vec2::Zero();
      step[a] = h;
      const WeightDerivatives P = W(y + step), M = W(y - step), P2 = W(y + 0.5 * step), M2 = W(y - 0.5 * step);
      auto rich = [&](double p, double m, double p2, double m2) { return (4.0 * (p2 - m2) / h - (p - m) / (2 * h)) / 3.0; };
      const double d = rich(P.W, M.W, P2.W, M2.W);
      const double d1 = rich(P.W1, M.W1, P2.W1, M2.W1), d2 = rich(P.W2, M.W2, P2.W2, M2.W2);
      const double exact = a == 0 ? D.W1 : D.W2;
      const double e1 = a == 0 ? D.W11 : D.W12, e2 = a == 0 ? D.W12 : D.W22;
      worst1 = std::max(worst1, std::abs(d - exact));
      worst2 = std::max({worst2, std::abs(d1 - e1), std::abs(d2 - e2)});
    }
  }
  std::printf("[ diffracted weight ] %d points: worst |dW - FD| %.1e, |ddW - FD| %.1e (support units)\n", checked,
              worst1, worst2);
  EXPECT_GT(checked, 500);
  EXPECT_LT(worst1, 1e-7);
  EXPECT_LT(worst2, 1e-5);
}

TEST(TipWeights, DiffractionBasisDerivativesMatchCentralDifferences) {
  // The whole basis near the tip, in cell units; stencils where the support factor changes are skipped.
  const TipScene s;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> off(-1.5, 1.5);
  double worst1 = 0.0, worst2 = 0.0;
  int checked = 0, skipped = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const Vec2 xi = kTip + kCell * Vec2(off(rng), off(rng));
    if (std::abs(xi.y() - kTip.y()) < 0.02 * kCell || (xi - kTip).norm() < 0.05 * kCell) continue;
    const Eval e = evaluate(s, xi, kDiffraction);
    if (e.fit.level != BasisLevel::Quadratic || e.fit.nudged) continue;
    for (int a = 0; a < 2; ++a) {
      const double h = 1e-4 * kCell;
      Vec2 step = Vec2::Zero();
      step[a] = h;
      const Eval P = evaluate(s, xi + step, kDiffraction), M = evaluate(s, xi - step, kDiffraction);
      const Eval P2 = evaluate(s, xi + 0.5 * step, kDiffraction), M2 = evaluate(s, xi - 0.5 * step, kDiffraction);
      bool same = true;
      for (const Eval* o : {&P, &M, &P2, &M2}) same &= o->factor == e.factor && o->R.size() == e.R.size();
      if (!same) {
        ++skipped;
        continue;
      }
      ++checked;
      for (const auto& [k, r] : e.R) {
        auto rich = [&](int j) {
          return (4.0 * (P2.R.at(k)[j] - M2.R.at(k)[j]) / h - (P.R.at(k)[j] - M.R.at(k)[j]) / (2 * h)) / 3.0;
        };
        const double d = rich(0) * kCell;
        const double exact = (a == 0 ? r[1] : r[2]) * kCell;
        const double d1 = rich(1) * kCell * kCell, d2 = rich(2) * kCell * kCell;
        const double e1 = (a == 0 ? r[3] : r[4]) * kCell * kCell, e2 = (a == 0 ? r[4] : r[5]) * kCell * kCell;
        worst1 = std::max(worst1, std::abs(d - exact));
        worst2 = std::max({worst2, std::abs(d1 - e1), std::abs(d2 - e2)});
      }
    }
  }
  std::printf("[ diffraction basis ] %d stencils (%d skipped at factor changes): worst |l dR - FD| %.1e, "
              "|l^2 ddR - FD| %.1e\n",
              checked, skipped, worst1, worst2);
  EXPECT_GT(checked, 100);
  EXPECT_LT(worst1, 1e-6);
  EXPECT_LT(worst2, 1e-4);
}

}  // namespace
}  // namespace shellfrac::shell
