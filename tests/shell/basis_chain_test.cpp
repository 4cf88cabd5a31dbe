// The fallback chain that leaves no material without a basis (shell/basis_chain.hpp, docs/mls.md), on
// crack graphs built by hand: a thin band with no control point inside, a pocket between two branches,
// closed loops smaller than a cell, a point on a crack line, and the unchanged rule near a crack tip.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "nurbs/patch_builders.hpp"
#include "shell/basis_chain.hpp"
#include "shell/shell_patch.hpp"
#include "tests/shell/shell_test_helpers.hpp"

namespace shellfrac::shell {
namespace {

using test::material;
using test::max_norm;

// A unit flat patch of 10 x 10 cells (l = 0.1): control points at 0, 0.05, 0.15, ..., 0.95, 1.
constexpr int kCells = 10;
constexpr double kCell = 1.0 / kCells;

struct Cracks {
  crack2d::CrackGraph graph;
  crack2d::CrackIndex index;
  crack2d::CrackPortals portals;
  void polyline(std::initializer_list<Vec2> pts, bool closed = false) {
    int first = -1, prev = -1;
    for (const Vec2& p : pts) {
      const int v = graph.add_vertex(p);
      if (prev >= 0) graph.add_edge(prev, v);
      if (first < 0) first = v;
      prev = v;
    }
    if (closed) graph.add_edge(prev, first);
  }
  void commit() {
    index.rebuild(graph);
    portals.build(index, 1e-7 * kCell);
  }
};

struct FlatPatch {
  nurbs::NurbsSurface surface = nurbs::flat_patch(1.0, 1.0, kCells, kCells);
  ControlGrid grid = ControlGrid::from_surface(surface);
  ShellPatch patch{surface, material(1e6, 0.3, 0.01)};
};

// Partition of unity and reproduction of the linear field xi (values and first derivatives), the
// consistency every level with a basis must have. Derivative sums are in parameter units (R_a ~ 1/l).
void expect_linear_reproduction(const MlsBasis& b, const ControlGrid& grid, const Vec2& at, double tol) {
  double s = 0, s1 = 0, s2 = 0;
  Vec2 x = Vec2::Zero(), x1 = Vec2::Zero(), x2 = Vec2::Zero();
  for (int k = 0; k < b.size(); ++k) {
    const Vec2 xk = grid.point(b.index[static_cast<size_t>(k)]);
    s += b.R[static_cast<size_t>(k)];
    s1 += b.R1[static_cast<size_t>(k)];
    s2 += b.R2[static_cast<size_t>(k)];
    x += b.R[static_cast<size_t>(k)] * xk;
    x1 += b.R1[static_cast<size_t>(k)] * xk;
    x2 += b.R2[static_cast<size_t>(k)] * xk;
  }
  EXPECT_NEAR(s, 1.0, tol);
  EXPECT_NEAR(s1 * kCell, 0.0, tol);
  EXPECT_NEAR(s2 * kCell, 0.0, tol);
  EXPECT_LE((x - at).norm(), tol * kCell);
  EXPECT_LE((x1 - Vec2(1, 0)).norm(), tol);
  EXPECT_LE((x2 - Vec2(0, 1)).norm(), tol);
}

TEST(BasisChain, ThinBandWithoutControlPointsTakesItsOwnSide) {
  // A full cut A at v = 0.52 splits the patch; a second cut B at v = 0.54 over u in [0.3, 0.6] leaves a
  // band 0.2 cells thick above A. It holds no control point (they sit at v = 0.45, 0.55) and is attached
  // to the upper fragment only around B's tips. Its points must take upper-fragment control points,
  // never ones across A (below it) or across B (above B, over its length).
  FlatPatch s;
  Cracks c;
  c.polyline({Vec2(0.0, 0.52), Vec2(1.0, 0.52)});
  c.polyline({Vec2(0.3, 0.54), Vec2(0.6, 0.54)});
  c.commit();
  BasisChainSettings settings;
  BasisChainWork work;
  int band_points = 0, fallbacks = 0;
  for (const Vec2& xi : s.patch.inplane_parameters()) {
    if (!(xi.y() > 0.52 && xi.y() < 0.54 && xi.x() > 0.3 && xi.x() < 0.6)) continue;
    ++band_points;
    const PointFit fit = fit_point_basis(xi, s.grid, c.index, c.portals, settings, work);
    SCOPED_TRACE("band point (" + std::to_string(xi.x()) + ", " + std::to_string(xi.y()) + ") level " +
                 basis_level_name(fit.level));
    ASSERT_LE(fit.level, BasisLevel::Fragment);
    EXPECT_FALSE(fit.chain_failed);
    fallbacks += fit.level >= BasisLevel::Linear;
    expect_linear_reproduction(work.basis, s.grid, xi, 1e-10);
    // Segment test: the straight line from each support point to the band's mid-line (same u) crosses
    // no crack: the point is on the band's side of A and of B.
    for (int k : work.basis.index) {
      const Vec2 xk = s.grid.point(k);
      EXPECT_FALSE(c.index.crosses(xk, Vec2(xk.x(), 0.53))) << "support point (" << xk.x() << ", " << xk.y() << ")";
    }
  }
  EXPECT_EQ(band_points, 12);  // 3 cells x 4 Gauss points at v = 0.533
  EXPECT_GT(fallbacks, 0);     // regression check: the band's inner points need the fallbacks
}

TEST(BasisChain, PocketBetweenBranchesAtASharpAngle) {
  // A crack from the left border forks at J = (0.5, 0.5) into two branches 12 degrees apart; the pocket
  // between them opens at u = 0.8. Every pocket point gets a basis whose support points are either seen
  // in a straight line or leave through the mouth (seen from its middle M); never behind a branch.
  FlatPatch s;
  Cracks c;
  const Vec2 J(0.5, 0.5), T1(0.8, 0.535), T2(0.8, 0.472), M(0.8, 0.5035);
  c.polyline({Vec2(0.0, 0.5), J});
  c.polyline({J, T1});
  c.polyline({J, T2});
  c.commit();
  const auto inside = [&](const Vec2& p) {
    return crack2d::orientation(J, T1, p) < 0 && crack2d::orientation(T1, T2, p) < 0 &&
           crack2d::orientation(T2, J, p) < 0;
  };
  BasisChainSettings settings;
  BasisChainWork work;
  int pocket_points = 0, fallbacks = 0;
  for (const Vec2& xi : s.patch.inplane_parameters()) {
    if (!inside(xi)) continue;
    ++pocket_points;
    const PointFit fit = fit_point_basis(xi, s.grid, c.index, c.portals, settings, work);
    SCOPED_TRACE("pocket point (" + std::to_string(xi.x()) + ", " + std::to_string(xi.y()) + ") level " +
                 basis_level_name(fit.level));
    ASSERT_LE(fit.level, BasisLevel::Fragment);
    fallbacks += fit.level >= BasisLevel::Linear;
    expect_linear_reproduction(work.basis, s.grid, xi, 1e-10);
    for (int k : work.basis.index) {
      const Vec2 xk = s.grid.point(k);
      EXPECT_TRUE(!c.index.crosses(xi, xk) || !c.index.crosses(M, xk))
          << "support point (" << xk.x() << ", " << xk.y() << ") lies behind a branch";
    }
  }
  EXPECT_GT(pocket_points, 3);
  EXPECT_GT(fallbacks, 0);  // regression check: the deepest points see too little in straight lines
}

// Area of in-plane point xi of the flat unit patch from the 4-point Gauss rule alone (independent of the
// patch's volumes): (l/2)^2 w_i w_j.
double gauss_area(const Vec2& xi) {
  const auto weight = [](double t) {
    const double local = 2.0 * (t / kCell - std::floor(t / kCell)) - 1.0;
    return std::abs(std::abs(local) - 0.8611363115940526) < 1e-9 ? 0.3478548451374538 : 0.6521451548625461;
  };
  return 0.25 * kCell * kCell * weight(xi.x()) * weight(xi.y());
}

TEST(BasisChain, LoopsSmallerThanACellBecomeRemovedAndRigidSliversWithTheirMassCounted) {
  // Two closed square cuts 0.4 cells wide: one holds no control point (its material is removed), the
  // other holds exactly the control point (0.55, 0.55) (a rigid sliver that moves with it).
  FlatPatch s;
  Cracks c;
  c.polyline({Vec2(0.48, 0.48), Vec2(0.52, 0.48), Vec2(0.52, 0.52), Vec2(0.48, 0.52)}, true);
  c.polyline({Vec2(0.53, 0.53), Vec2(0.57, 0.53), Vec2(0.57, 0.57), Vec2(0.53, 0.57)}, true);
  c.commit();
  const auto in_box = [](const Vec2& p, double lo, double hi) {
    return p.x() > lo && p.x() < hi && p.y() > lo && p.y() < hi;
  };
  ShellPatch& p = s.patch;
  const CrackUpdate u = p.update_crack(c.index, 0, MlsSettings{});
  double removed_area = 0, rigid_area = 0;
  size_t removed = 0, rigid = 0;
  for (size_t q = 0; q < p.num_inplane_points(); ++q) {
    const Vec2& xi = p.parameter(q);
    const BasisLevel level = p.point_level(q);
    if (in_box(xi, 0.48, 0.52)) {
      EXPECT_EQ(level, BasisLevel::Removed);
      removed_area += gauss_area(xi);
      ++removed;
    } else if (in_box(xi, 0.53, 0.57)) {
      EXPECT_EQ(level, BasisLevel::Rigid);
      rigid_area += gauss_area(xi);
      ++rigid;
    } else {
      EXPECT_LE(level, BasisLevel::Fragment);
    }
  }
  EXPECT_EQ(removed, 4u);
  EXPECT_EQ(rigid, 4u);
  const BasisCensus& census = u.census;
  EXPECT_EQ(census.points[static_cast<size_t>(BasisLevel::Removed)], 4u);
  EXPECT_EQ(census.points[static_cast<size_t>(BasisLevel::Rigid)], 4u);
  EXPECT_EQ(census.slivers(), 8u);
  EXPECT_EQ(census.failures, 0u);
  EXPECT_EQ(p.num_mls_failures(), 0u);
  // The shear particle at the cell centre (0.55, 0.55) is inside the rigid loop.
  EXPECT_EQ(census.shear[static_cast<size_t>(BasisLevel::Rigid)], 1u);
  // Area and mass exactly (flat patch: area = Gauss weight x cell area; mass = density x thickness x area).
  EXPECT_NEAR(census.removed_area, removed_area, 1e-15);
  EXPECT_NEAR(census.rigid_area, rigid_area, 1e-15);
  EXPECT_NEAR(census.removed_mass, 500.0 * 0.01 * removed_area, 1e-13);
  EXPECT_NEAR(census.rigid_mass, 500.0 * 0.01 * rigid_area, 1e-13);

  // The rigid sliver follows its control point by a translation and costs no force; render vertices in
  // the removed loop say so.
  const int k = 6 + 12 * 6;  // control point (0.55, 0.55): index 6 in each direction of the 12 x 12 grid
  ASSERT_LE((p.control_parameter(static_cast<size_t>(k)) - Vec2(0.55, 0.55)).norm(), 1e-15);
  BasisChainWork work;
  const Vec2 inside_rigid(0.56, 0.54), inside_removed(0.5, 0.5);
  const Vec3 before = p.surface_point(inside_rigid, work).position;
  EXPECT_LE((before - Vec3(0.56, 0.54, 0.0)).norm(), 1e-14);
  const Vec3 d(0.01, -0.02, 0.03);
  p.x[static_cast<size_t>(k)] += d;
  const ShellPatch::SurfacePoint moved = p.surface_point(inside_rigid, work);
  EXPECT_EQ(moved.level, BasisLevel::Rigid);
  EXPECT_LE((moved.position - before - d).norm(), 1e-14);
  EXPECT_EQ(p.surface_point(inside_removed, work).level, BasisLevel::Removed);
  ASSERT_FALSE(p.compute_forces().failed);
  EXPECT_EQ(p.force[static_cast<size_t>(k)].norm(), 0.0);
  // Everything else is still in its rest state: no force anywhere.
  EXPECT_LE(max_norm(p.force), 1e-9);
}

TEST(BasisChain, PointOnACrackLineTakesOneSide) {
  // A diagonal crack runs exactly through the Gauss points of the diagonal cells (u = v), as extracted
  // cracks do in symmetric scenes. Such a point sees nothing; it is moved 1e-9 cells to one side.
  FlatPatch s;
  Cracks c;
  c.polyline({Vec2(0.2, 0.2), Vec2(0.8, 0.8)});
  c.commit();
  BasisChainSettings settings;
  BasisChainWork work;
  int on_crack = 0;
  for (const Vec2& xi : s.patch.inplane_parameters()) {
    if (!(xi.x() == xi.y() && xi.x() > 0.3 && xi.x() < 0.7)) continue;
    ASSERT_TRUE(c.index.crosses(xi, xi));
    ++on_crack;
    const PointFit fit = fit_point_basis(xi, s.grid, c.index, c.portals, settings, work);
    EXPECT_TRUE(fit.nudged);
    EXPECT_LE((fit.at - xi).norm(), 1e-8 * kCell);
    EXPECT_LE(fit.level, BasisLevel::RelaxedQuadratic);
    expect_linear_reproduction(work.basis, s.grid, fit.at, 1e-10);
    int side = 0;
    for (int k : work.basis.index) {
      const Vec2 xk = s.grid.point(k);
      if (xk.x() == xk.y()) {  // on the crack's line: only beyond its ends, where both sides see it
        EXPECT_TRUE(xk.x() < 0.2 || xk.x() > 0.8);
        continue;
      }
      const int o = xk.y() > xk.x() ? 1 : -1;
      if (side == 0) side = o;
      EXPECT_EQ(o, side) << "support points on both sides of the crack";
    }
  }
  EXPECT_EQ(on_crack, 16);  // 4 diagonal cells x 4 points
}

TEST(BasisChain, NearACrackTipOrdinaryPointsKeepTheStraightLineRule) {
  // A slit from the border to the tip (0.5, 0.5): the points around the tip whose NURBS support it cuts
  // get exactly the basis of thesis sec. 4.6 (mls_basis with straight-line visibility), so none takes a
  // control point seen only around the tip from the other side.
  FlatPatch s;
  Cracks c;
  c.polyline({Vec2(0.0, 0.5), Vec2(0.5, 0.5)});
  c.commit();
  BasisChainSettings settings;
  BasisChainWork work;
  MlsBasis direct;
  auto visible = [&](const Vec2& a, const Vec2& b) { return !c.index.crosses(a, b); };
  int near_tip = 0;
  for (const Vec2& xi : s.patch.inplane_parameters()) {
    if ((xi - Vec2(0.5, 0.5)).lpNorm<Eigen::Infinity>() > 1.5 * kCell) continue;
    ++near_tip;
    const PointFit fit = fit_point_basis(xi, s.grid, c.index, c.portals, settings, work);
    EXPECT_EQ(fit.level, BasisLevel::Quadratic);
    ASSERT_TRUE(mls_basis(xi, s.grid, visible, settings.mls, direct));
    ASSERT_EQ(work.basis.index, direct.index);
    for (size_t k = 0; k < direct.R.size(); ++k) EXPECT_EQ(work.basis.R11[k], direct.R11[k]);
    for (int k : work.basis.index) EXPECT_FALSE(c.index.crosses(xi, s.grid.point(k)));
  }
  EXPECT_EQ(near_tip, 144);  // 12 x 12 Gauss points within 1.5 cells of the tip
}

TEST(BasisChain, PatchWithFallbackPointsKeepsForcesTheEnergyGradient) {
  // The band of the first test inside a shell patch: fallback points (linear, membrane only, and
  // fragment ones) must still give forces that are minus the gradient of the energy they define, sum to
  // zero, and leave nothing without a basis.
  ShellPatch p(nurbs::flat_patch(1.0, 1.0, kCells, kCells), material(1e6, 0.3, 0.01));
  Cracks c;
  c.polyline({Vec2(0.0, 0.52), Vec2(1.0, 0.52)});
  c.polyline({Vec2(0.3, 0.54), Vec2(0.6, 0.54)});
  c.commit();
  const CrackUpdate u = p.update_crack(c.index, 0, MlsSettings{});
  EXPECT_EQ(u.failures, 0u);
  EXPECT_EQ(u.census.slivers(), 0u);
  EXPECT_GT(u.census.membrane_only + u.census.points[static_cast<size_t>(BasisLevel::Fragment)], 0u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> r(-0.01, 0.01);
  for (auto& x : p.x) x += Vec3(r(rng), r(rng), r(rng));
  ASSERT_FALSE(p.compute_forces().failed);
  const std::vector<Vec3> f = p.force;
  EXPECT_LE(test::energy_gradient_mismatch(p, f, 3), 1e-6 * max_norm(f));
  Vec3 sum = Vec3::Zero();
  for (const auto& v : f) sum += v;
  EXPECT_LE(sum.norm(), 1e-11 * max_norm(f) * static_cast<double>(f.size()));
}

}  // namespace
}  // namespace shellfrac::shell
