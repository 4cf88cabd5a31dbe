// The support rule of cut bases (shell/mls_basis.hpp SupportRule, docs/mls.md "Support size"): along a
// crack face the stepped growth makes the support factor, and with it the basis, jump between points a
// fraction of a cell apart; the continuous rule moves both continuously, and still reproduces quadratics.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "nurbs/patch_builders.hpp"
#include "shell/basis_chain.hpp"

namespace shellfrac::shell {
namespace {

using Vec2 = Eigen::Vector2d;

// A unit flat patch of 10 x 10 quadratic cells (l = 0.1), cut from its left edge along v = 0.503 to a
// tip at u = 0.523 (off the control point rows and columns).
struct CutPatch {
  ControlGrid grid = ControlGrid::from_surface(nurbs::flat_patch(1.0, 1.0, 10, 10));
  crack2d::CrackGraph graph;
  crack2d::CrackIndex index;
  crack2d::CrackPortals portals;
  CutPatch() {
    graph.add_edge(graph.add_vertex(Vec2(0.0, 0.503)), graph.add_vertex(Vec2(0.523, 0.503)));
    index.rebuild(graph);
    portals.build(index, 1e-8);
  }
};

struct Sample {
  double factor = 0.0;
  int level = 0;
  std::map<int, double> R;
};

Sample evaluate(const CutPatch& s, const Vec2& xi, SupportRule rule) {
  BasisChainSettings settings;
  settings.mls.tip.mode = TipWeights::Mode::diffraction;
  settings.mls.rule = rule;
  BasisChainWork work;
  Sample out;
  out.level = static_cast<int>(fit_point_basis(xi, s.grid, s.index, s.portals, settings, work).level);
  const MlsBasis& b = work.basis;
  out.factor = b.factor;
  for (int k = 0; k < b.size(); ++k) out.R[b.index[static_cast<size_t>(k)]] = b.R[static_cast<size_t>(k)];
  return out;
}

double basis_jump(const Sample& a, const Sample& b) {
  double jump = 0.0;
  for (const auto& [k, r] : a.R) jump = std::max(jump, std::abs(r - (b.R.count(k) ? b.R.at(k) : 0.0)));
  for (const auto& [k, r] : b.R)
    if (!a.R.count(k)) jump = std::max(jump, std::abs(r));
  return jump;
}

struct Scan {
  double factor_step = 0.0;  // largest change of the support factor between neighbouring samples
  double basis_step = 0.0;   // largest basis jump between neighbouring samples
  double smallest = 1e9, largest = 0.0;
};

// Samples every h (parameter units) along a line below the crack, u in [0.05, 0.40]: every point's NURBS
// support is cut, and the tip is more than a cell away.
Scan scan_face(const CutPatch& s, double v, double h, SupportRule rule) {
  Scan out;
  Sample prev = evaluate(s, Vec2(0.05, v), rule);
  for (double u = 0.05 + h; u <= 0.40; u += h) {
    Sample cur = evaluate(s, Vec2(u, v), rule);
    EXPECT_EQ(cur.level, prev.level) << u;
    out.factor_step = std::max(out.factor_step, std::abs(cur.factor - prev.factor));
    out.basis_step = std::max(out.basis_step, basis_jump(prev, cur));
    out.smallest = std::min(out.smallest, cur.factor);
    out.largest = std::max(out.largest, cur.factor);
    prev = std::move(cur);
  }
  return out;
}

TEST(SupportRule, ContinuousSupportMovesContinuouslyAlongACrackFace) {
  const CutPatch s;
  for (double v : {0.49, 0.45}) {  // 0.13 and 0.53 cells below the crack
    const Scan stepped = scan_face(s, v, 1e-4, SupportRule::stepped);
    const Scan coarse = scan_face(s, v, 1e-4, SupportRule::continuous);
    const Scan fine = scan_face(s, v, 1e-5, SupportRule::continuous);
    std::printf("[ face at v = %.2f ] stepped: factor %.3f..%.3f, largest step %.3f, basis jump %.2e; "
                "continuous: factor %.3f..%.3f, largest step %.2e / %.2e, basis jump %.2e / %.2e (h = 1e-4 / 1e-5)\n",
                v, stepped.smallest, stepped.largest, stepped.factor_step, stepped.basis_step, coarse.smallest,
                coarse.largest, coarse.factor_step, fine.factor_step, coarse.basis_step, fine.basis_step);
    // The negative control: the stepped growth jumps by a whole growth step (1.25x) somewhere on the face.
    EXPECT_GT(stepped.factor_step, 0.3);
    EXPECT_GT(stepped.basis_step, 10.0 * coarse.basis_step);
    // Continuous: the factor is margin x a distance (or the factor where the conditioning test flips) and
    // shrinks with h (h = 1e-4 is 1e-3 cells); so does the basis jump: no jump is left at any scale
    // above the bisection's 1e-4 of the factor.
    EXPECT_LT(coarse.factor_step, 1e-2);
    EXPECT_LT(fine.factor_step, 0.2 * coarse.factor_step);
    EXPECT_LT(fine.basis_step, 0.2 * coarse.basis_step);
  }
}

TEST(SupportRule, ContinuousBasisIsAPartitionOfUnityAndReproducesQuadratics) {
  const CutPatch s;
  BasisChainSettings settings;
  settings.mls.tip.mode = TipWeights::Mode::diffraction;
  settings.mls.rule = SupportRule::continuous;
  BasisChainWork work;
  double worst = 0.0;
  for (double u = 0.02; u < 0.98; u += 0.037) {
    for (double v = 0.41; v < 0.6; v += 0.013) {
      const Vec2 xi(u, v);
      fit_point_basis(xi, s.grid, s.index, s.portals, settings, work);
      const MlsBasis& b = work.basis;
      if (!b.ok || b.size() < 6) continue;  // NURBS points (support not cut) have no MLS basis here
      // sum R_k f(xi_k) = f(xi) for f = 1, u, v, u^2, u v, v^2 (cell-scaled).
      for (int t = 0; t < 6; ++t) {
        double sum = 0.0, exact = 0.0;
        auto f = [&](const Vec2& p) {
          const Vec2 q = p / 0.1;
          const double val[6] = {1.0, q.x(), q.y(), q.x() * q.x(), q.x() * q.y(), q.y() * q.y()};
          return val[t];
        };
        for (int k = 0; k < b.size(); ++k) sum += b.R[static_cast<size_t>(k)] * f(s.grid.point(b.index[static_cast<size_t>(k)]));
        exact = f(xi);
        worst = std::max(worst, std::abs(sum - exact) / std::max(1.0, std::abs(exact)));
      }
    }
  }
  std::printf("continuous support: worst relative quadratic reproduction error %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(SupportRule, MarginAtOrBelowOneIsRefused) {
  MlsSettings settings;
  settings.rule = SupportRule::continuous;
  settings.support_margin = 1.0;
  MlsBasis out;
  ControlPointList none;
  none.cell_u = none.cell_v = 0.1;
  EXPECT_FALSE(mls_basis(Vec2(0.5, 0.5), none, AlwaysVisible{}, settings, out));
  EXPECT_EQ(out.status, MlsStatus::invalid_input);
  EXPECT_NE(out.reason.find("support_margin"), std::string::npos) << out.reason;
}

}  // namespace
}  // namespace shellfrac::shell
