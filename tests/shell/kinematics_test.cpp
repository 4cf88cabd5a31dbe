// The analytic derivative of the Kirchhoff-Love bases (and so of F^KL) with respect to the control
// points, including the normal's dependence on them, against central finite differences.
#include "shell/kinematics.hpp"

#include <gtest/gtest.h>

#include <random>

#include "nurbs/patch_builders.hpp"

namespace shellfrac::shell {
namespace {

struct Fixture {
  std::vector<Vec3> points;
  std::vector<double> d;  // 9 x {R1 R2 R11 R12 R22}
};

// A doubly curved, sheared 3x3 control net and the basis derivatives at an interior point.
Fixture make_fixture() {
  const auto surf = nurbs::flat_patch(1.0, 1.0, 1, 1);  // 3 x 3 control points, one cell
  nurbs::SurfaceBasis b;
  surf.rational_basis(0.37, 0.61, b);
  Fixture f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  for (const auto& p : surf.control_points()) f.points.push_back(p + Vec3(u(rng), u(rng), 2 * u(rng)));
  f.d.resize(45);
  for (int k = 0; k < 9; ++k) {
    const int i = b.index[k];
    f.d[5 * i + 0] = b.Ru[k];
    f.d[5 * i + 1] = b.Rv[k];
    f.d[5 * i + 2] = b.Ruu[k];
    f.d[5 * i + 3] = b.Ruv[k];
    f.d[5 * i + 4] = b.Rvv[k];
  }
  return f;
}

SurfaceJet jet_of(const std::vector<Vec3>& pts, const std::vector<double>& d) {
  const Vec3* ptr[9];
  for (int i = 0; i < 9; ++i) ptr[i] = &pts[static_cast<size_t>(i)];
  return surface_jet(ptr, d.data(), 9);
}

// Gradient of E(x) = sum over layers of Kf_l : F_l(x) with F_l = G_l(x) Gbar_l^-1, analytic vs FD.
TEST(KirchhoffLoveKinematics, DeformationGradientDerivativeMatchesFiniteDifferences) {
  Fixture f = make_fixture();
  const std::vector<double> xi3 = {-0.02, 0.0, 0.03};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Mat3> Kf, Gbar_inv;
  for (size_t l = 0; l < xi3.size(); ++l) {
    Mat3 k, gb;
    for (int i = 0; i < 9; ++i) k(i / 3, i % 3) = u(rng);
    for (int i = 0; i < 9; ++i) gb(i / 3, i % 3) = u(rng) + (i % 4 == 0 ? 3.0 : 0.0);  // well conditioned
    Kf.push_back(k);
    Gbar_inv.push_back(gb);
  }
  auto energy = [&](const std::vector<Vec3>& pts) {
    const SurfaceJet s = jet_of(pts, f.d);
    NormalJet n;
    EXPECT_TRUE(normal_jet(s, n));
    double e = 0;
    for (size_t l = 0; l < xi3.size(); ++l) e += (Kf[l].array() * (kl_basis(s, n, xi3[l]) * Gbar_inv[l]).array()).sum();
    return e;
  };
  // Analytic: Kf : (G Gbar^-1) = (Kf Gbar^-T) : G, so dE/dg_i = column i of Kf Gbar^-T.
  const SurfaceJet s = jet_of(f.points, f.d);
  NormalJet n;
  ASSERT_TRUE(normal_jet(s, n));
  Vec3 K1 = Vec3::Zero(), K2 = Vec3::Zero(), C1 = Vec3::Zero(), C2 = Vec3::Zero(), K3 = Vec3::Zero();
  for (size_t l = 0; l < xi3.size(); ++l) {
    const Mat3 k = Kf[l] * Gbar_inv[l].transpose();
    K1 += k.col(0);
    K2 += k.col(1);
    C1 += xi3[l] * k.col(0);
    C2 += xi3[l] * k.col(1);
    K3 += k.col(2);
  }
  const JetGradient g = kl_basis_adjoint(s, n, K1, K2, C1, C2, K3);
  double worst = 0, scale = 0;
  for (int p = 0; p < 9; ++p) {
    const double* r = &f.d[5 * static_cast<size_t>(p)];
    const Vec3 analytic = r[0] * g.a1 + r[1] * g.a2 + r[2] * g.a11 + r[3] * g.a12 + r[4] * g.a22;
    for (int c = 0; c < 3; ++c) {
      const double h = 1e-6;
      auto plus = f.points, minus = f.points;
      plus[static_cast<size_t>(p)][c] += h;
      minus[static_cast<size_t>(p)][c] -= h;
      const double fd = (energy(plus) - energy(minus)) / (2 * h);
      worst = std::max(worst, std::abs(fd - analytic[c]));
      scale = std::max(scale, std::abs(fd));
    }
  }
  EXPECT_GT(scale, 1e-2);
  EXPECT_LE(worst, 1e-7 * scale);
}

TEST(KirchhoffLoveKinematics, BasisIsOrthonormalThroughTheThickness) {
  const Fixture f = make_fixture();
  const SurfaceJet s = jet_of(f.points, f.d);
  NormalJet n;
  ASSERT_TRUE(normal_jet(s, n));
  for (double xi3 : {-0.05, 0.0, 0.05}) {
    const Mat3 G = kl_basis(s, n, xi3);
    // g_3 is the unit normal and stays orthogonal to g_1, g_2 at every layer (a_3,alpha is tangent).
    EXPECT_NEAR(G.col(2).norm(), 1.0, 1e-15);
    EXPECT_NEAR(G.col(2).dot(G.col(0)), 0.0, 1e-14);
    EXPECT_NEAR(G.col(2).dot(G.col(1)), 0.0, 1e-14);
  }
  NormalJet degenerate;
  SurfaceJet flat = s;
  flat.a2 = 2.0 * flat.a1;
  EXPECT_FALSE(normal_jet(flat, degenerate));
}

}  // namespace
}  // namespace shellfrac::shell
