#include "shell/shell_patch.hpp"
#include "tests/shell/shell_test_helpers.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "nurbs/patch_builders.hpp"
#include "shell/quadrature.hpp"

namespace shellfrac::shell {
namespace {

using test::material;
using test::energy_gradient_mismatch;
using test::max_norm;


TEST(ShellPatch, CountsAndMassFollowTheThesisLayout) {
  const ShellPatch p(nurbs::flat_patch(2.0, 1.0, 8, 4), material(1e6, 0.3, 0.01));
  EXPECT_EQ(p.num_control_points(), 10u * 6u);
  EXPECT_EQ(p.num_cells(), 32u);
  EXPECT_EQ(p.num_quadrature_points(), 32u * 16u * 3u);  // 4x4 stencil, 3 layers
  double total = 0;
  for (double m : p.mass) total += m;
  EXPECT_NEAR(total, (1 - kShearParticleMassShare) * 500 * 0.01 * 2.0, 1e-12);  // control points' share
  for (double m : p.shear.mass) total += m;
  EXPECT_NEAR(total, 500 * 0.01 * 2.0, 1e-12);  // rho tau A over Types II and III
  EXPECT_NEAR(p.reference_volume(), 0.02, 1e-15);
  for (double m : p.mass) EXPECT_GT(m, 0);
}

TEST(ShellPatch, RigidMotionGivesZeroForce) {
  // A curved (rational cylinder) shell, rotated and translated: no strain, no force.
  ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 2.0, 6, 5), material(1e6, 0.3, 0.01));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (auto& x : p.x) x = R * x + Vec3(3, -1, 2);
  ASSERT_FALSE(p.compute_forces().failed);
  const double rigid = max_norm(p.force);
  // Reference scale: the forces of a 1% stretch.
  ShellPatch q(nurbs::cylinder_segment(0.5, 1.0, 2.0, 6, 5), material(1e6, 0.3, 0.01));
  for (auto& x : q.x) x *= 1.01;
  ASSERT_FALSE(q.compute_forces().failed);
  const double stretched = max_norm(q.force);
  EXPECT_GT(stretched, 1.0);
  EXPECT_LE(rigid, 1e-10 * stretched);
  EXPECT_NEAR(p.elastic_energy(), 0.0, 1e-12 * q.elastic_energy());
}

TEST(ShellPatch, ForceIsMinusEnergyGradientAndConservesMomentum) {
  ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 1.5, 4, 3), material(1e6, 0.3, 0.05));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.03, 0.03);
  for (auto& x : p.x) x += Vec3(u(rng), u(rng), u(rng));
  ASSERT_FALSE(p.compute_forces().failed);
  const std::vector<Vec3> f = p.force;
  const double scale = max_norm(f);
  EXPECT_LE(energy_gradient_mismatch(p, f, 3), 1e-6 * scale);
  // Internal forces sum to zero (translation invariance) and have no net torque (rotation invariance).
  Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
  for (size_t i = 0; i < f.size(); ++i) {
    sum += f[i];
    torque += p.x[i].cross(f[i]);
  }
  EXPECT_LE(sum.norm(), 1e-11 * scale * static_cast<double>(f.size()));
  EXPECT_LE(torque.norm(), 1e-11 * scale * static_cast<double>(f.size()));
}

TEST(ShellPatch, ShearParticleForcesAreEnergyGradients) {
  // Compressed, sheared directors with friction: the Type III force on the control points is minus the
  // energy gradient, and the grid stress term carries dPsi/dd_3 (S = dPsi/dd_3 (x) d_3).
  ShellMaterial m = material(1e6, 0.3, 0.02);
  m.shear = {3e5, 1e6, 0.5};
  ShellPatch p(nurbs::flat_patch(1.0, 1.0, 3, 3), m);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (auto& d : p.shear.director) d = Vec3(u(rng), u(rng), 0.8 + u(rng));
  for (auto& x : p.x) x += Vec3(u(rng), u(rng), u(rng)) * 0.2;
  ASSERT_FALSE(p.compute_forces().failed);
  const std::vector<Vec3> f = p.force;
  EXPECT_LE(energy_gradient_mismatch(p, f, 1), 1e-6 * max_norm(f));
  for (size_t c = 0; c < p.shear.director.size(); c += 2) {
    const Vec3 d3 = p.shear.director[c];
    const Vec3 g3 = p.shear.stress[c] * d3 / d3.squaredNorm();
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-7;
      p.shear.director[c][k] = d3[k] + h;
      const double ep = p.elastic_energy();
      p.shear.director[c][k] = d3[k] - h;
      const double em = p.elastic_energy();
      p.shear.director[c][k] = d3[k];
      EXPECT_NEAR((ep - em) / (2 * h), g3[k], 1e-5 * g3.norm() + 1e-9);
    }
  }
}

TEST(ShellPatch, ShearParticlesFollowTheSurface) {
  ShellMaterial m = material(1e6, 0.3, 0.01);
  ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 1.5, 6, 4), m);
  ASSERT_EQ(p.shear.x.size(), p.num_cells());
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Vec3(0, 0, 1)).toRotationMatrix();
  for (auto& x : p.x) x = R * x;
  p.update_shear_particles(0.0);
  for (size_t c = 0; c < p.num_cells(); ++c) {
    // On the rotated cylinder (axis y, radius 0.5) and at the cell centre's surface point.
    const Vec3& x = p.shear.x[c];
    const Vec3 local = R.transpose() * x;
    EXPECT_NEAR(std::hypot(local.x(), local.z()), 0.5, 1e-12);
  }
}

TEST(ShellPatch, UniformStretchTractionMatchesPlaneStress) {
  // A flat 1 x 0.5 sheet stretched uniformly by 2% along x with the exact lateral contraction of
  // plane-stress uniaxial tension: interior control points feel no force, and the force on the x = L
  // edge is the traction P_11 * thickness * width.
  const double E = 2e6, nu = 0.3, tau = 0.002, L = 1.0, W = 0.5, e = 0.02;
  ShellPatch p(nurbs::flat_patch(L, W, 8, 4), material(E, nu, tau));
  const double mu = p.material().mu, lambda = p.material().lambda;
  double lo = 0.5, hi = 1.2;  // lateral = thickness stretch s: mu (s^2 - 1) + lambda ln((1+e) s^2) = 0
  for (int i = 0; i < 200; ++i) {
    const double s = 0.5 * (lo + hi);
    (mu * (s * s - 1) + lambda * std::log((1 + e) * s * s) > 0 ? hi : lo) = s;
  }
  const double s = 0.5 * (lo + hi);
  for (auto& x : p.x) x = Vec3((1 + e) * x.x(), s * x.y(), 0);
  ASSERT_FALSE(p.compute_forces().failed);
  const double P11 = mu * ((1 + e) * (1 + e) - s * s) / (1 + e);
  double edge = 0, interior = 0;
  for (size_t i = 0; i < p.x.size(); ++i) {
    const int iu = static_cast<int>(i) % 10, jv = static_cast<int>(i) / 10;
    if (iu == 9) edge += p.force[i].x();
    if (iu > 1 && iu < 8 && jv > 1 && jv < 4) interior = std::max(interior, p.force[i].norm());
  }
  EXPECT_NEAR(-edge, P11 * tau * W, 1e-9 * P11 * tau * W);
  EXPECT_LE(interior, 1e-9 * P11 * tau * W);
}

// Control point heights that make a quadratic B-spline reproduce z = a x^2 exactly: the blossom
// (polar form) of x^2 at the two interior knots of each basis function, scaled to the patch size.
TEST(ShellPatch, CylindricalBendingEnergyMatchesPlateTheory) {
  const double E = 1e6, nu = 0.3, tau = 0.01, L = 1.0, a = 1e-4;
  const auto surf = nurbs::flat_patch(L, L, 10, 10);
  ShellPatch p(surf, material(E, nu, tau));
  const auto& k = surf.knots_u();
  for (size_t idx = 0; idx < p.x.size(); ++idx) {
    const int i = static_cast<int>(idx) % surf.num_u();
    p.x[idx].z() = a * (k[i + 1] * L) * (k[i + 2] * L);
  }
  // z = a x^2 has curvature 2a (to O(a^2)); strain along y is zero, so D = E tau^3 / (12 (1 - nu^2)).
  const double D = E * tau * tau * tau / (12 * (1 - nu * nu));
  const double expected = 0.5 * D * (2 * a) * (2 * a) * L * L;
  EXPECT_NEAR(p.elastic_energy(), expected, 2e-3 * expected);
}

TEST(ShellPatch, CollapsedElementIsReported) {
  // A KL shell cannot invert locally (g_3 follows g_1 x g_2), but it can collapse: squash the sheet onto
  // a line and every layer has zero area.
  ShellPatch p(nurbs::flat_patch(1, 1, 2, 2), material(1e6, 0.3, 0.01));
  for (auto& x : p.x) x.y() = 0;
  const ForceFailure f = p.compute_forces();
  EXPECT_TRUE(f.failed);
  EXPECT_EQ(f.quadrature_point, 0u);
  EXPECT_NE(f.reason.find("degenerate"), std::string::npos);
}

}  // namespace
}  // namespace shellfrac::shell

namespace shellfrac::shell {
namespace {

TEST(ShellPatch, ComparisonStressModelsAreEnergyGradients) {
  // Plane strain (Guo 2018 style: full 3D stress with the fibre kept) and the 2D mid-surface model
  // (Jiang 2017 style) are exact gradients of their energies; plane strain differs from the projected
  // thesis stress by the transverse normal stress tau^33 = lambda ln J acting through the normal.
  for (StressModel model : {StressModel::PlaneStrain, StressModel::MidSurface2D}) {
    ShellMaterial m = material(1e6, 0.3, 0.05);
    m.stress_model = model;
    ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 1.5, 4, 3), m);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.03, 0.03);
    for (auto& x : p.x) x += Vec3(u(rng), u(rng), u(rng));
    ASSERT_FALSE(p.compute_forces().failed);
    const std::vector<Vec3> f = p.force;
    EXPECT_LE(energy_gradient_mismatch(p, f, 3), 1e-6 * max_norm(f)) << static_cast<int>(model);
  }
}

TEST(ShellPatch, MidSurfaceModelIsTheMembraneOfTheRigidFibreShell) {
  // On a flat reference the 2D model at every layer equals the rigid-fibre shell sampled on the
  // mid-surface only (one layer): the same membrane energy, and no bending. The three-layer shell adds
  // bending energy on top.
  const nurbs::NurbsSurface flat = nurbs::flat_patch(1.0, 0.6, 6, 4);
  ShellMaterial mid = material(1e6, 0.3, 0.02), rigid = material(1e6, 0.3, 0.02, TransverseModel::Rigid);
  mid.stress_model = StressModel::MidSurface2D;
  QuadratureRule one_layer;
  one_layer.layers = 1;
  ShellPatch p2d(flat, mid), membrane(flat, rigid, one_layer), shell(flat, rigid);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  std::vector<Vec3> moved = p2d.x;
  for (auto& x : moved) x += Vec3(u(rng), u(rng), 3 * u(rng));
  for (ShellPatch* p : {&p2d, &membrane, &shell}) p->x = moved;
  EXPECT_NEAR(p2d.elastic_energy(), membrane.elastic_energy(), 1e-12 * membrane.elastic_energy());
  EXPECT_GT(shell.elastic_energy(), 1.01 * p2d.elastic_energy());
}

TEST(ShellPatch, DirectorModelSeesTheDirectorsNormalStretch) {
  // The Jiang 2017 model with F = [a_1 a_2 d_3] D^-1: compressing every Type III director to r_33 = 0.8
  // changes only the volume ratio, J = J_2D r_33. At rest the Type IV energy then differs from the 2D
  // mid-surface model by V (mu/2 (r33^2 - 1) - mu ln r33 + lambda/2 ln^2 r33) (Neo-Hookean, Eq. 2.3).
  const nurbs::NurbsSurface flat = nurbs::flat_patch(1.0, 0.6, 6, 4);
  ShellMaterial mid = material(1e6, 0.3, 0.02), director = mid;
  mid.stress_model = StressModel::MidSurface2D;
  director.stress_model = StressModel::DirectorF2D;
  ShellPatch p2d(flat, mid), pd(flat, director);
  const double r33 = 0.8;
  for (ShellPatch* p : {&p2d, &pd})
    for (Vec3& d : p->shear.director) d *= r33;
  for (size_t c = 0; c < pd.shear.director.size(); ++c) EXPECT_NEAR(pd.director_stretch(c), r33, 1e-14);
  const double mu = director.mu, lambda = director.lambda, l = std::log(r33);
  const double expected = pd.reference_volume() * (0.5 * mu * (r33 * r33 - 1) - mu * l + 0.5 * lambda * l * l);
  EXPECT_NEAR(pd.elastic_energy() - p2d.elastic_energy(), expected, 1e-9 * std::abs(expected));
  // In-plane motions keep the normal, hence r_33: there the forces are the exact energy gradient.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  for (auto& x : pd.x) x += Vec3(u(rng), u(rng), 0);
  ASSERT_FALSE(pd.compute_forces().failed);
  const std::vector<Vec3> f = pd.force;
  EXPECT_LE(energy_gradient_mismatch(pd, f, 3, 2), 1e-6 * max_norm(f));
}

}  // namespace
}  // namespace shellfrac::shell

namespace shellfrac::shell {
namespace {

TEST(ShellPatch, RunawayStretchIsReportedNotComputed) {
  // A diverging explicit step shows up as absurd stretch long before it overflows to NaN: scaling the
  // sheet 40 times in both directions (area ratio 1600 > 1000) is reported with its cell.
  ShellPatch p(nurbs::flat_patch(1.0, 1.0, 4, 4), material(1e5, 0.3, 0.001));
  ASSERT_FALSE(p.compute_forces().failed);
  for (auto& x : p.x) x *= 40.0;
  const ForceFailure f = p.compute_forces();
  ASSERT_TRUE(f.failed);
  EXPECT_NE(f.reason.find("more than 1000 times its area in cell"), std::string::npos) << f.reason;
  for (auto& x : p.x) x *= 30.0 / 40.0;  // area ratio 900: still a (huge) deformation, computed
  EXPECT_FALSE(p.compute_forces().failed);
}

}  // namespace
}  // namespace shellfrac::shell

namespace shellfrac::shell {
namespace {

// Gauss-Legendre rules of 1 to 8 points integrate x^k over [-1, 1] exactly for k <= 2n - 1 (the rules of
// six to eight points are computed by Newton on P_n), and are refused beyond 8.
TEST(GaussLegendre, RulesIntegratePolynomialsOfDegreeTwoNMinusOneExactly) {
  for (int n = 1; n <= 8; ++n) {
    const GaussRule g = gauss_legendre(n);
    ASSERT_EQ(g.x.size(), static_cast<size_t>(n));
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += g.w[static_cast<size_t>(i)] * std::pow(g.x[static_cast<size_t>(i)], k);
      const double exact = k % 2 ? 0.0 : 2.0 / (k + 1);
      EXPECT_NEAR(sum, exact, 1e-14) << n << " points, x^" << k;
    }
    double beyond = 0;  // and not x^2n: the rule is not exact beyond its order
    for (int i = 0; i < n; ++i) beyond += g.w[static_cast<size_t>(i)] * std::pow(g.x[static_cast<size_t>(i)], 2 * n);
    EXPECT_GT(std::abs(beyond - 2.0 / (2 * n + 1)), 1e-6) << n;
  }
  EXPECT_THROW(gauss_legendre(9), std::invalid_argument);
}

}  // namespace
}  // namespace shellfrac::shell
