// A shell patch with cracks: MLS bases where the crack cuts a NURBS support (thesis sec. 4.6) and Rankine
// damage with healing (sec. 4.4.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "nurbs/patch_builders.hpp"
#include "shell/shell_patch.hpp"
#include "tests/shell/shell_test_helpers.hpp"

namespace shellfrac::shell {
namespace {

using test::material;
using test::energy_gradient_mismatch;
using test::max_norm;

// A crack made of one straight polyline in the parameter plane, and its index.
struct Crack {
  crack2d::CrackGraph graph;
  crack2d::CrackIndex index;
  void add(const Vec2& a, const Vec2& b) {
    const int i = graph.add_vertex(a), j = graph.add_vertex(b);
    graph.add_edge(i, j);
  }
  size_t commit() {  // returns the first new edge
    const size_t first = index.num_segments();
    index.add_edges(graph, first);
    return first;
  }
};

TEST(ShellCracks, CrackedForceIsMinusEnergyGradient) {
  ShellPatch p(nurbs::flat_patch(1.0, 1.0, 8, 8), material(1e6, 0.3, 0.01));
  Crack crack;
  crack.add(Vec2(0.0, 0.5), Vec2(0.3, 0.52));
  crack.add(Vec2(0.3, 0.52), Vec2(0.62, 0.47));
  const CrackUpdate u = p.update_crack(crack.index, crack.commit(), MlsSettings{});
  EXPECT_GT(u.mls_points, 50u);
  EXPECT_GT(u.mls_shear, 3u);
  EXPECT_EQ(u.failures, 0u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> r(-0.02, 0.02);
  for (auto& x : p.x) x += Vec3(r(rng), r(rng), r(rng));
  ASSERT_FALSE(p.compute_forces().failed);
  const std::vector<Vec3> f = p.force;
  EXPECT_LE(energy_gradient_mismatch(p, f, 2), 1e-6 * max_norm(f));
  Vec3 sum = Vec3::Zero();
  for (const auto& v : f) sum += v;
  EXPECT_LE(sum.norm(), 1e-11 * max_norm(f) * static_cast<double>(f.size()));
}

// The MLS points run the batched kernel in lanes grouped by support size (padded with zero basis
// entries): every control point force and every layer point's damage equal the scalar kernel's to
// round-off (1e-12 of the largest force), and so do the forces with only the MLS points scalar
// (ForceKernel::BatchedScalarMls), on a fracturing patch with a forked crack, so that supports of
// several sizes share batches.
TEST(ShellCracks, BatchedMlsForcesEqualTheScalarKernel) {
  ShellMaterial m = material(1e6, 0.3, 0.01);
  m.fracture.enabled = true;
  m.fracture.failure_stress = 2e4;
  ShellPatch batched(nurbs::flat_patch(1.0, 1.0, 10, 10), m);
  batched.set_brittleness(1.0);
  Crack crack;
  crack.add(Vec2(0.0, 0.5), Vec2(0.43, 0.52));
  crack.add(Vec2(0.43, 0.52), Vec2(0.81, 0.77));
  crack.add(Vec2(0.43, 0.52), Vec2(0.74, 0.21));
  const CrackUpdate u = batched.update_crack(crack.index, crack.commit(), MlsSettings{});
  ASSERT_GT(u.mls_points, 100u);
  // Nearly all MLS points go to the lanes (linear bases, if any, stay scalar).
  EXPECT_GE(batched.num_batched_mls_points(), u.mls_points - u.census.membrane_only);
  EXPECT_GT(batched.num_batched_mls_points(), 100u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> r(-0.02, 0.02);
  for (auto& x : batched.x) x = 1.05 * x + Vec3(r(rng), r(rng), r(rng));
  ShellPatch scalar = batched, scalar_mls = batched;
  scalar.set_force_kernel(ForceKernel::Scalar);
  scalar_mls.set_force_kernel(ForceKernel::BatchedScalarMls);
  ASSERT_FALSE(batched.compute_forces().failed);
  ASSERT_FALSE(scalar.compute_forces().failed);
  ASSERT_FALSE(scalar_mls.compute_forces().failed);
  double worst = 0, worst_mls = 0;
  for (size_t i = 0; i < batched.force.size(); ++i) {
    worst = std::max(worst, (batched.force[i] - scalar.force[i]).norm());
    worst_mls = std::max(worst_mls, (batched.force[i] - scalar_mls.force[i]).norm());
  }
  EXPECT_LE(worst, 1e-12 * max_norm(scalar.force));
  EXPECT_LE(worst_mls, 1e-12 * max_norm(scalar.force));
  EXPECT_GT(worst_mls, 0.0);  // the MLS points did run another kernel
  EXPECT_GT(batched.max_damage(), 0.0);  // the damage law is exercised
  for (size_t k = 0; k < batched.damage_values().size(); ++k)
    EXPECT_NEAR(batched.damage_values()[k], scalar.damage_values()[k], 1e-12);
}

TEST(ShellCracks, MovingOneFragmentRigidlyCostsNoForce) {
  // A crack right across the patch: translating and rotating the upper fragment's control points is a
  // rigid motion of that fragment, so no point may feel a force. Without the crack it tears the sheet.
  const nurbs::NurbsSurface surface = nurbs::flat_patch(1.0, 0.8, 8, 6);
  ShellPatch cracked(surface, material(1e6, 0.3, 0.01)), intact(surface, material(1e6, 0.3, 0.01));
  Crack crack;
  crack.add(Vec2(0.0, 0.5), Vec2(1.0, 0.5));
  cracked.update_crack(crack.index, crack.commit(), MlsSettings{});
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vec3(0.2, 1.0, 0.4).normalized()).toRotationMatrix();
  for (ShellPatch* p : {&cracked, &intact})
    for (size_t k = 0; k < p->x.size(); ++k)
      if (p->control_parameter(k).y() > 0.5) p->x[k] = R * p->x[k] + Vec3(0.1, 0.3, -0.2);
  ASSERT_FALSE(cracked.compute_forces().failed);
  ASSERT_FALSE(intact.compute_forces().failed);
  EXPECT_GT(max_norm(intact.force), 1.0);
  EXPECT_LE(max_norm(cracked.force), 1e-10 * max_norm(intact.force));
  EXPECT_EQ(cracked.num_mls_failures(), 0u);
}

TEST(ShellCracks, OnlyPointsNearNewSegmentsAreRebuilt) {
  ShellPatch p(nurbs::flat_patch(1.0, 1.0, 20, 20), material(1e6, 0.3, 0.01));
  Crack crack;
  crack.add(Vec2(0.0, 0.5), Vec2(0.4, 0.5));
  const CrackUpdate first = p.update_crack(crack.index, crack.commit(), MlsSettings{});
  crack.add(Vec2(0.8, 0.8), Vec2(0.85, 0.82));
  const CrackUpdate second = p.update_crack(crack.index, crack.commit(), MlsSettings{});
  const size_t points = p.num_inplane_points() + p.num_cells();
  // A 0.05 x 0.02 segment touches supports within 1.5 cells (0.075): about 0.2 x 0.17 of the patch.
  EXPECT_GT(second.examined, 0u);
  EXPECT_LE(second.examined, points / 20);
  EXPECT_GT(first.examined, second.examined);
  EXPECT_GT(second.mls_points, first.mls_points);
}

// Uniform biaxial stretch of a flat patch: control points scaled by s in the plane.
void stretch(ShellPatch& p, const nurbs::NurbsSurface& rest, double s) {
  for (size_t k = 0; k < p.x.size(); ++k) p.x[k] = s * rest.control_points()[k];
}

TEST(ShellCracks, DamageWeakensTensionAndHealsUnlessMonotone) {
  const nurbs::NurbsSurface rest = nurbs::flat_patch(1.0, 1.0, 4, 4);
  ShellMaterial m = material(1e6, 0.3, 0.01);
  m.fracture.enabled = true;
  m.fracture.failure_stress = 5e4;
  m.brittleness = 0.5;
  ShellPatch intact(rest, material(1e6, 0.3, 0.01)), healing(rest, m);
  m.fracture.rule = DamageRule::Monotone;
  ShellPatch monotone(rest, m);
  for (ShellPatch* p : {&intact, &healing, &monotone}) {
    stretch(*p, rest, 1.05);
    ASSERT_FALSE(p->compute_forces().failed);
  }
  // Equibiaxial tension: both principal stresses are tensile, so every force scales by (1 - c).
  const double c = healing.damage(0, 1);
  EXPECT_GT(c, 0.05);
  EXPECT_LT(c, 1.0);
  for (size_t q = 0; q < healing.num_inplane_points(); ++q) EXPECT_NEAR(healing.damage(q, 1), c, 1e-9);
  for (size_t k = 0; k < intact.x.size(); ++k)
    EXPECT_LE((healing.force[k] - (1 - c) * intact.force[k]).norm(), 1e-9 * max_norm(intact.force));
  // The effective stress is the undamaged one: c follows Eq. 2.28 with H = 0.5, i.e.
  // sigma_bar = sigma_f / (1 - c / (1 + H)).
  const double sigma_bar = 5e4 / (1.0 - c / 1.5);
  EXPECT_GT(sigma_bar, 5e4);
  // Unloading: healing damage returns to 0 while its history stays; monotone damage stays.
  for (ShellPatch* p : {&healing, &monotone}) {
    stretch(*p, rest, 1.0);
    ASSERT_FALSE(p->compute_forces().failed);
  }
  EXPECT_EQ(healing.damage(0, 1), 0.0);
  EXPECT_NEAR(healing.damage_history(0, 1), c, 1e-15);
  EXPECT_NEAR(monotone.damage(0, 1), c, 1e-15);
  // Reloading: the healed material is as stiff as before, the monotone one stays weakened.
  for (ShellPatch* p : {&healing, &monotone}) {
    stretch(*p, rest, 1.02);
    ASSERT_FALSE(p->compute_forces().failed);
  }
  stretch(intact, rest, 1.02);
  ASSERT_FALSE(intact.compute_forces().failed);
  const double scale = max_norm(intact.force);
  EXPECT_GT(scale, 1.0);
  for (size_t k = 0; k < intact.x.size(); ++k) {
    EXPECT_LE((healing.force[k] - intact.force[k]).norm(), 1e-9 * scale);
    EXPECT_LE((monotone.force[k] - (1 - c) * intact.force[k]).norm(), 1e-9 * scale);
  }
}

}  // namespace
}  // namespace shellfrac::shell

namespace shellfrac::shell {
namespace {

// The count of fully damaged points (the crack extraction's trigger) against the per-point histories: a
// patch whose right half is pulled far past the failure stress, so part of it reaches c = 1 and part not.
TEST(ShellCracks, FullyDamagedCountMatchesTheHistories) {
  const nurbs::NurbsSurface rest = nurbs::flat_patch(1.0, 1.0, 8, 8);
  ShellMaterial m = material(1e6, 0.3, 0.01);
  m.fracture.enabled = true;
  m.fracture.failure_stress = 5e4;
  m.brittleness = 0.5;
  ShellPatch p(rest, m);
  ASSERT_FALSE(p.compute_forces().failed);
  EXPECT_EQ(p.num_fully_damaged_points(), 0u);  // unloaded: nothing damaged
  for (size_t k = 0; k < p.x.size(); ++k) {
    const Vec3& x0 = rest.control_points()[k];
    p.x[k] = x0 + Vec3(x0.x() > 0.6 ? 0.4 * (x0.x() - 0.6) : 0.0, 0.0, 0.0);  // 40% stretch right of x = 0.6
  }
  ASSERT_FALSE(p.compute_forces().failed);
  size_t want = 0;
  for (size_t q = 0; q < p.num_inplane_points(); ++q) {
    bool full = false;
    for (int l = 0; l < p.num_layers(); ++l) full = full || p.damage_history(q, l) >= 1.0;
    want += full;
  }
  EXPECT_GT(want, 0u);
  EXPECT_LT(want, p.num_inplane_points());
  EXPECT_EQ(p.num_fully_damaged_points(), want);
  const std::vector<unsigned char> listed = p.fully_damaged_points();
  EXPECT_EQ(static_cast<size_t>(std::count(listed.begin(), listed.end(), 1)), want);
}

}  // namespace
}  // namespace shellfrac::shell
