// Rankine damage with tensile weakening (thesis Eq. 2.28-2.31, sec. 4.4.1).
#include "shell/damage.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

namespace shellfrac::shell {
namespace {

Mat3 assemble(const InPlaneTensor& t, const Vec3& g1, const Vec3& g2) {
  return t.t11 * g1 * g1.transpose() + t.t12 * (g1 * g2.transpose() + g2 * g1.transpose()) +
         t.t22 * g2 * g2.transpose();
}

// Independent reference: the 3D tensor's eigen-decomposition with positive eigenvalues scaled by (1-c).
Mat3 weaken_reference(const Mat3& s, double c) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(s);
  Vec3 l = es.eigenvalues();
  for (int i = 0; i < 3; ++i)
    if (l[i] > 0) l[i] *= 1.0 - c;
  return es.eigenvectors() * l.asDiagonal() * es.eigenvectors().transpose();
}

struct Sample {
  Vec3 g1, g2;
  InPlaneTensor t;
};

Sample random_sample(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Sample s;
  s.g1 = Vec3(1.0 + 0.3 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
  s.g2 = Vec3(0.3 * u(rng), 0.8 + 0.3 * u(rng), 0.2 * u(rng));
  s.t = {u(rng), u(rng), u(rng)};
  return s;
}

TEST(Damage, BrittlenessFollowsTheCharacteristicLength) {
  // Hbar = sigma_f^2 / (2 E G_f) = 1e12 / (2 * 1e9 * 100) = 5 /m; l = 0.1 m -> Hbar l = 0.5, H = 1.
  EXPECT_NEAR(brittleness(1e6, 100.0, 1e9, 0.1), 1.0, 1e-14);
  // Hbar l >= 1 snaps back: reported as negative.
  EXPECT_LT(brittleness(1e6, 100.0, 1e9, 0.2), 0.0);
  EXPECT_LT(brittleness(1e6, 0.0, 1e9, 0.1), 0.0);
}

TEST(Damage, RankineLinearSofteningBranches) {
  const double sf = 2.0, H = 0.5;  // full damage at sf (1 + 1/H) = 6
  EXPECT_EQ(rankine_damage(1.9, sf, H), 0.0);
  EXPECT_EQ(rankine_damage(2.0, sf, H), 0.0);
  EXPECT_NEAR(rankine_damage(4.0, sf, H), 1.5 * (1.0 - 0.5), 1e-15);
  EXPECT_NEAR(rankine_damage(6.0 - 1e-9, sf, H), 1.0, 1e-9);  // continuous at the end of softening
  EXPECT_EQ(rankine_damage(6.0, sf, H), 1.0);
  EXPECT_EQ(rankine_damage(100.0, sf, H), 1.0);
  EXPECT_EQ(rankine_damage(-5.0, sf, H), 0.0);
}

TEST(Damage, LargestPrincipalMatchesTheThreeDimensionalEigenvalues) {
  std::mt19937 rng(7);
  for (int k = 0; k < 200; ++k) {
    const Sample s = random_sample(rng);
    const Mat3 tau = assemble(s.t, s.g1, s.g2);
    Eigen::SelfAdjointEigenSolver<Mat3> es(tau);
    // One eigenvalue is the zero normal stress (sigma g_3 = 0); the largest in-plane one is what we compute.
    const Vec3 l = es.eigenvalues();
    const double scale = l.cwiseAbs().maxCoeff();
    double in_plane_max = -1e300;
    for (int i = 0; i < 3; ++i) {
      const Vec3 q = es.eigenvectors().col(i);
      const double normal_part = std::abs(q.dot(s.g1.cross(s.g2).normalized()));
      if (normal_part < 0.5) in_plane_max = std::max(in_plane_max, l[i]);
    }
    EXPECT_NEAR(largest_principal(s.t, s.g1, s.g2), in_plane_max, 1e-12 * scale);
  }
}

TEST(Damage, WeakeningScalesOnlyTheTensilePrincipalPart) {
  std::mt19937 rng(11);
  for (int k = 0; k < 200; ++k) {
    const Sample s = random_sample(rng);
    const double c = (k % 5) / 4.0;  // 0, 0.25, ..., 1
    const Mat3 tau = assemble(s.t, s.g1, s.g2);
    const Mat3 expected = weaken_reference(tau, c);
    const Mat3 got = assemble(weaken_tensile_part(s.t, s.g1, s.g2, c), s.g1, s.g2);
    EXPECT_LE((got - expected).norm(), 1e-12 * (1.0 + tau.norm())) << "sample " << k << " c " << c;
  }
}

TEST(Damage, FullDamageLeavesOnlyCompression) {
  // Uniaxial tension along g_1 with compression along g_2 in an orthonormal frame.
  const Vec3 g1(1, 0, 0), g2(0, 1, 0);
  const InPlaneTensor t{3.0, 0.0, -2.0};
  const InPlaneTensor w = weaken_tensile_part(t, g1, g2, 1.0);
  EXPECT_NEAR(w.t11, 0.0, 1e-15);
  EXPECT_NEAR(w.t12, 0.0, 1e-15);
  EXPECT_NEAR(w.t22, -2.0, 1e-15);
  const InPlaneTensor h = weaken_tensile_part(t, g1, g2, 0.25);
  EXPECT_NEAR(h.t11, 2.25, 1e-15);
}

}  // namespace
}  // namespace shellfrac::shell
