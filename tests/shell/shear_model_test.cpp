#include "shell/shear_model.hpp"

#include <gtest/gtest.h>

#include <random>

namespace shellfrac::shell {
namespace {

const ShearParams kParams{2.0e4, 5.0e4, 0.4};

Mat3 random_compressed_F(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  Mat3 F = Mat3::Identity();
  for (int i = 0; i < 9; ++i) F(i / 3, i % 3) += u(rng);
  F.col(2) *= 0.7;  // compress the director so that r33 < 1
  return F;
}

TEST(ShearModel, QrKeepsOrientationAndUpperTriangle) {
  std::mt19937 rng(1);
  for (int t = 0; t < 10; ++t) {
    Mat3 F = random_compressed_F(rng);
    if (t % 2) F.col(2) = -F.col(2);  // flipped director
    Mat3 Q, R;
    qr_oriented(F, Q, R);
    EXPECT_LE((Q * R - F).norm(), 1e-14);
    EXPECT_NEAR(Q.determinant(), 1.0, 1e-14);
    EXPECT_GT(R(0, 0), 0);
    EXPECT_GT(R(1, 1), 0);
    EXPECT_EQ(R(2, 2) < 0, t % 2 == 1);  // the sign of r33 tells a flipped director
  }
}

TEST(ShearModel, StressIsTheEnergyDerivative) {
  std::mt19937 rng(2);
  for (int t = 0; t < 10; ++t) {
    const Mat3 F = random_compressed_F(rng);
    const Mat3 P = shear_pk1(F, kParams);
    auto psi = [&](const Mat3& G) {
      Mat3 Q, R;
      qr_oriented(G, Q, R);
      return shear_energy_density(R, kParams);
    };
    double worst = 0;
    for (int i = 0; i < 9; ++i) {
      const double h = 1e-7;
      Mat3 a = F, b = F;
      a(i / 3, i % 3) += h;
      b(i / 3, i % 3) -= h;
      worst = std::max(worst, std::abs((psi(a) - psi(b)) / (2 * h) - P(i / 3, i % 3)));
    }
    EXPECT_LE(worst, 1e-6 * P.norm());
    EXPECT_GT(P.norm(), 1.0);
  }
}

TEST(ShearModel, ReturnMappingSeparatesAndAppliesCoulombFriction) {
  // Stretched director (r33 > 1): separation resets shear and normal to rest, d_3 = q_3.
  Mat3 F = Mat3::Identity();
  F.col(2) = Vec3(0.2, -0.1, 1.3);
  EXPECT_LE((shear_return_map(F, kParams) - Vec3(0, 0, 1)).norm(), 1e-15);
  // Compressed with large shear: projected onto the cone |r_s| = c_F k (1 - r33)^2 / gamma.
  F.col(2) = Vec3(0.5, 0.0, 0.8);
  const double limit = 0.4 * 5.0e4 * 0.2 * 0.2 / 2.0e4;
  EXPECT_LE((shear_return_map(F, kParams) - Vec3(limit, 0, 0.8)).norm(), 1e-14);
  // Inside the cone: unchanged.
  F.col(2) = Vec3(0.01, 0.01, 0.8);
  EXPECT_LE((shear_return_map(F, kParams) - F.col(2)).norm(), 1e-15);
  // No friction: the shear part always vanishes, compression stays.
  ShearParams frictionless = kParams;
  frictionless.friction = 0;
  F.col(2) = Vec3(0.01, 0.02, 0.9);
  EXPECT_LE((shear_return_map(F, frictionless) - Vec3(0, 0, 0.9)).norm(), 1e-15);
}

TEST(ShearModel, EnergyValues) {
  Mat3 R = Mat3::Identity();
  R(0, 2) = 0.1;
  R(1, 2) = 0.2;
  R(2, 2) = 0.7;
  EXPECT_NEAR(shear_energy_density(R, kParams), 0.5 * 2.0e4 * 0.05 + 5.0e4 / 3.0 * 0.027, 1e-9);
  R(2, 2) = 1.2;  // no normal energy in tension
  EXPECT_NEAR(shear_energy_density(R, kParams), 0.5 * 2.0e4 * 0.05, 1e-9);
}

}  // namespace
}  // namespace shellfrac::shell
