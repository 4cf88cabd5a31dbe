#include "shell/plasticity.hpp"

#include <gtest/gtest.h>

namespace shellfrac::shell {
namespace {

constexpr double kE = 2e8, kNu = 0.3;
const double kMu = kE / (2 * (1 + kNu)), kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu));

ReferenceLayer flat_rest() { return reference_layer(Mat3::Identity()); }

TEST(Plasticity, ElasticBelowYield) {
  PlasticityParams p{true, 1e6, 0.0};
  ReferenceLayer rest = flat_rest();
  double alpha = 0;
  EXPECT_FALSE(von_mises_return(Vec3(1.001, 0, 0), Vec3(0, 1, 0), kMu, kLambda, p, rest, alpha));
  EXPECT_EQ(alpha, 0.0);
  EXPECT_EQ(rest.g11, 1.0);
}

TEST(Plasticity, ReturnLandsOnTheYieldSurface) {
  for (double H : {0.0, 5e6}) {
    PlasticityParams p{true, 1e6, H};
    ReferenceLayer rest = flat_rest();
    double alpha = 0;
    const Vec3 g1(1.03, 0.01, 0), g2(0.0, 0.99, 0);
    EXPECT_GT(von_mises_stress(g1, g2, kMu, kLambda, rest), 5e6);  // far beyond yield
    EXPECT_TRUE(von_mises_return(g1, g2, kMu, kLambda, p, rest, alpha));
    EXPECT_GT(alpha, 0.0);
    // On the surface to the Hencky/Neo-Hookean difference at 0.5% elastic strain (< 1%).
    EXPECT_NEAR(von_mises_stress(g1, g2, kMu, kLambda, rest), 1e6 + H * alpha, 0.01 * (1e6 + H * alpha));
    // A second return at the same state does nothing: it is on the surface.
    double alpha2 = alpha;
    ReferenceLayer again = rest;
    EXPECT_FALSE(von_mises_return(g1, g2, kMu, kLambda, p, again, alpha2) && alpha2 > alpha * (1 + 1e-9));
  }
}

TEST(Plasticity, EquibiaxialStretchLeavesAPermanentSet) {
  // Stretch 5% equibiaxially, yield, then find the unloaded state: the rest metric is isotropic, and the
  // tangents that make it stress-free are the permanent stretch (> 1, < 1.05).
  PlasticityParams p{true, 1e6, 0.0};
  ReferenceLayer rest = flat_rest();
  double alpha = 0;
  const double stretch = 1.05;
  ASSERT_TRUE(von_mises_return(Vec3(stretch, 0, 0), Vec3(0, stretch, 0), kMu, kLambda, p, rest, alpha));
  EXPECT_NEAR(rest.g12, 0.0, 1e-14);
  EXPECT_NEAR(rest.g11, rest.g22, 1e-12);
  const double permanent = 1.0 / std::sqrt(rest.g11);
  EXPECT_GT(permanent, 1.04);
  EXPECT_LT(permanent, stretch);
  EXPECT_NEAR(von_mises_stress(Vec3(permanent, 0, 0), Vec3(0, permanent, 0), kMu, kLambda, rest), 0.0, 1e-6 * 1e6);
  const InPlaneStress unloaded =
      neo_hookean_in_plane(Vec3(permanent, 0, 0), Vec3(0, permanent, 0), rest, kMu, kLambda, TransverseModel::Condensed);
  EXPECT_NEAR(unloaded.t11, 0.0, 1e-6 * 1e6);
}

}  // namespace
}  // namespace shellfrac::shell
