#include "brittle/damage.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace shellfrac::brittle {
namespace {

TEST(Damage, RankineLinearSofteningBranches) {
  // thesis Eq. 2.28 with sigma_f = 200, H = 0.5: 0 below, (1 + H)(1 - sigma_f / s) on the branch, 1 from
  // sigma_f (1 + 1/H) = 600 on.
  EXPECT_EQ(rankine_damage(150, 200, 0.5), 0.0);
  EXPECT_EQ(rankine_damage(200, 200, 0.5), 0.0);
  EXPECT_NEAR(rankine_damage(300, 200, 0.5), 1.5 * (1 - 200.0 / 300), 1e-15);
  EXPECT_NEAR(rankine_damage(599.999, 200, 0.5), 1.0, 1e-5);  // continuous at the end of the branch
  EXPECT_EQ(rankine_damage(600, 200, 0.5), 1.0);
  EXPECT_EQ(rankine_damage(1e9, 200, 0.5), 1.0);
}

TEST(Damage, BrittlenessFromFractureEnergy) {
  // Hbar = sigma_f^2 / (2 E G_f) = 200^2 / (2 * 3.2e8 * 200) = 3.125e-7; with l = 0.01 Hbar l = 3.125e-9.
  const double h = brittleness(200, 200, 3.2e8, 0.01);
  EXPECT_NEAR(h, 3.125e-9 / (1 - 3.125e-9), 1e-22);
  EXPECT_LT(brittleness(1e6, 1.0, 1e6, 1.0), 0);  // Hbar l >= 1: invalid, reported by the caller
}

TEST(Damage, TensilePartIsWeakenedCompressionKept) {
  // A symmetric tensor with principal values (3, -2, 1) in a rotated frame.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d s = R * Eigen::Vector3d(3, -2, 1).asDiagonal() * R.transpose();
  double largest = 0;
  const Eigen::Matrix3d w = weaken_tensile_part(s, 0.75, &largest);
  EXPECT_NEAR(largest, 3.0, 1e-13);
  const Eigen::Matrix3d expected = R * Eigen::Vector3d(0.75, -2, 0.25).asDiagonal() * R.transpose();
  EXPECT_LT((w - expected).norm(), 1e-13);
  // Fully damaged: no tension left, compression untouched.
  const Eigen::Matrix3d broken = weaken_tensile_part(s, 1.0);
  EXPECT_LT((broken - R * Eigen::Vector3d(0, -2, 0).asDiagonal() * R.transpose()).norm(), 1e-13);
  // Gershgorin bound is an upper bound of the largest eigenvalue.
  EXPECT_GE(largest_eigenvalue_bound(s), 3.0 - 1e-13);
}

TEST(Damage, DamageStepUnderUniaxialStretch) {
  // Stretch 1.01 along x, rest volume 1e-6: the effective stress is tau(F)/J of the Neo-Hookean solid; its
  // largest principal value decides c (Eq. 2.28) and the returned stress is V^0 J sigma(F, c).
  const double mu = 1e6, lambda = 1.5e6, V = 1e-6;
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 0) = 1.01;
  const double J = 1.01;
  const double s1 = (mu * (1.01 * 1.01 - 1) + lambda * std::log(J)) / J;  // sigma_xx
  const double s2 = lambda * std::log(J) / J;                           // sigma_yy = sigma_zz
  const double sf = 0.8 * s1, H = 0.2;
  ParticleDamage st;
  const Eigen::Matrix3d S = damage_step(F, V, mu, lambda, sf, H, DamageRule::Healing, 0.0, 0.5, st);
  const double c = (1 + H) * (1 - sf / s1);
  EXPECT_NEAR(st.c, c, 1e-12);
  EXPECT_NEAR(st.c_his, c, 1e-12);
  EXPECT_EQ(st.tau, -1.0);  // not fully damaged yet
  EXPECT_NEAR(S(0, 0), V * J * (1 - c) * s1, 1e-9 * V * s1);
  EXPECT_NEAR(S(1, 1), V * J * (1 - c) * s2, 1e-9 * V * s1);  // also tensile here (ln J > 0)
  // Unloading: healing returns to c = 0 and keeps c_his; monotone keeps c.
  ParticleDamage healing = st, monotone = st;
  damage_step(Eigen::Matrix3d::Identity(), V, mu, lambda, sf, H, DamageRule::Healing, 0.0, 1.0, healing);
  damage_step(Eigen::Matrix3d::Identity(), V, mu, lambda, sf, H, DamageRule::Monotone, 0.0, 1.0, monotone);
  EXPECT_EQ(healing.c, 0.0);
  EXPECT_NEAR(healing.c_his, c, 1e-12);
  EXPECT_NEAR(monotone.c, c, 1e-12);
  // Past sigma_f (1 + 1/H): fully damaged, the damage time is recorded once.
  Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
  G(0, 0) = 1.2;
  ParticleDamage full;
  damage_step(G, V, mu, lambda, sf, H, DamageRule::Healing, 0.0, 2.0, full);
  EXPECT_EQ(full.c, 1.0);
  EXPECT_EQ(full.tau, 2.0);
  damage_step(G, V, mu, lambda, sf, H, DamageRule::Healing, 0.0, 3.0, full);
  EXPECT_EQ(full.tau, 2.0);
}

// Guards against slab-sphere's crushed patch: the damage law must not damage under compression and
// must weaken only tension. Hydrostatic and confined uniaxial compression (all principal stresses < 0)
// leave c = 0 and the undamaged stress even for a tiny sigma_f; a stretched-and-squeezed state that is
// fully damaged keeps its compressive principal stress exactly (thesis Eq. 2.29-2.31).
TEST(Damage, CompressionNeverDamagesAndKeepsItsStress) {
  const double mu = 1e6, lambda = 1.5e6, V = 1e-6, sf = 1.0, H = 0.5;
  for (const Eigen::Vector3d& stretch : {Eigen::Vector3d(0.97, 0.97, 0.97), Eigen::Vector3d(0.9, 1.0, 1.0)}) {
    const Eigen::Matrix3d F = stretch.asDiagonal();
    ParticleDamage st;
    const Eigen::Matrix3d S = damage_step(F, V, mu, lambda, sf, H, DamageRule::Monotone, 0.0, 1.0, st);
    EXPECT_EQ(st.c, 0.0) << stretch.transpose();
    EXPECT_EQ(st.c_his, 0.0);
    EXPECT_LT((S - V * neo_hookean_kirchhoff(F, mu, lambda)).norm(), 1e-12 * V * mu);
  }
  // Stretch 1.3 along x, squeeze 0.7 along y in a rotated frame: x in tension far past sigma_f (1 + 1/H),
  // y in compression. Fully damaged: the tensile principal stress is gone, the compressive one is kept.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  const Eigen::Matrix3d F = R * Eigen::Vector3d(1.3, 0.7, 1.0).asDiagonal() * R.transpose();
  const double J = 1.3 * 0.7;
  const double sx = (mu * (1.3 * 1.3 - 1) + lambda * std::log(J)) / J, sy = (mu * (0.7 * 0.7 - 1) + lambda * std::log(J)) / J,
               sz = lambda * std::log(J) / J;
  ASSERT_GT(sx, sf * (1 + 1 / H));
  ASSERT_LT(sy, 0.0);
  ASSERT_LT(sz, 0.0);
  ParticleDamage st;
  const Eigen::Matrix3d S = damage_step(F, V, mu, lambda, sf, H, DamageRule::Healing, 0.0, 1.0, st);
  EXPECT_EQ(st.c, 1.0);
  const Eigen::Matrix3d expected = V * J * (R * Eigen::Vector3d(0.0, sy, sz).asDiagonal() * R.transpose());
  EXPECT_LT((S - expected).norm(), 1e-9 * V * mu);
}

// With a residual stiffness r the tensile principal stresses are scaled by 1 - (1 - r) c (c = 1: r of the
// undamaged value), the compressive ones are kept, and r = 0 is the thesis's Eq. 2.30 exactly.
TEST(Damage, ResidualStiffnessKeepsItsShareOfTheTensileStress) {
  const double mu = 1e6, lambda = 1.5e6, V = 1e-6, sf = 1.0, H = 0.5, r = 1e-3;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  const Eigen::Matrix3d F = R * Eigen::Vector3d(1.3, 0.7, 1.0).asDiagonal() * R.transpose();
  const double J = 1.3 * 0.7;
  const double sx = (mu * (1.3 * 1.3 - 1) + lambda * std::log(J)) / J, sy = (mu * (0.7 * 0.7 - 1) + lambda * std::log(J)) / J,
               sz = lambda * std::log(J) / J;
  ParticleDamage full;
  const Eigen::Matrix3d S = damage_step(F, V, mu, lambda, sf, H, DamageRule::Healing, r, 1.0, full);
  ASSERT_EQ(full.c, 1.0);
  const Eigen::Matrix3d expected = V * J * (R * Eigen::Vector3d(r * sx, sy, sz).asDiagonal() * R.transpose());
  EXPECT_LT((S - expected).norm(), 1e-9 * V * mu);
  // Partly damaged (uniaxial stretch as above): 1 - (1 - r) c on both tensile principal stresses.
  Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
  G(0, 0) = 1.01;
  const double s1 = (mu * (1.01 * 1.01 - 1) + lambda * std::log(1.01)) / 1.01;
  ParticleDamage part;
  const Eigen::Matrix3d P = damage_step(G, V, mu, lambda, 0.8 * s1, 0.2, DamageRule::Healing, 0.05, 1.0, part);
  ASSERT_GT(part.c, 0.0);
  ASSERT_LT(part.c, 1.0);
  EXPECT_NEAR(P(0, 0), V * 1.01 * (1 - 0.95 * part.c) * s1, 1e-9 * V * s1);
}

TEST(Damage, StretchLimitCapsOnlyTheStretchAboveItAndKeepsTheRotations) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(-0.3, Eigen::Vector3d(0, 1, 0)).toRotationMatrix();
  // A runaway: stretched 40x along one axis, squeezed to 0.2 across it, rotated on both sides.
  Eigen::Matrix3d F = R * Eigen::Vector3d(40.0, 0.2, 1.0).asDiagonal() * Q;
  EXPECT_TRUE(limit_stretch(F, 3.0));
  EXPECT_LT((F - R * Eigen::Vector3d(3.0, 1.0 / 3.0, 1.0).asDiagonal() * Q).norm(), 1e-12);
  // Below the limit nothing moves, bit for bit.
  Eigen::Matrix3d G = R * Eigen::Vector3d(2.9, 0.35, 1.2).asDiagonal() * Q;
  const Eigen::Matrix3d G0 = G;
  EXPECT_FALSE(limit_stretch(G, 3.0));
  EXPECT_EQ(G, G0);
}

}  // namespace
}  // namespace shellfrac::brittle
