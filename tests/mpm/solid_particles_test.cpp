#include "mpm/solid_particles.hpp"

#include <gtest/gtest.h>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

TEST(Sampling, JitteredFillsTheShapeAtTheRequestedDensity) {
  const Sphere ball(Vec3(0.1, 0.2, 0.3), 0.2);
  const double h = 0.02;
  const auto pts = sample_jittered(ball, Vec3(-0.1, 0, 0.1), Vec3(0.3, 0.4, 0.5), h, 7);
  for (const auto& p : pts) EXPECT_LT(ball.signed_distance(p), 0.0);
  const double expected = 4.0 / 3.0 * 3.14159265358979 * 0.008 / (h * h * h);  // volume / h^3 = 4189
  EXPECT_NEAR(static_cast<double>(pts.size()), expected, 0.03 * expected);
}

TEST(Sampling, PoissonDiskKeepsTheMinimumDistance) {
  const Box box(Vec3(0, 0, 0), Vec3(0.1, 0.05, 0.05));
  const double h = 0.02;
  const auto pts = sample_poisson_disk(box, Vec3(-0.1, -0.05, -0.05), Vec3(0.1, 0.05, 0.05), h, 3);
  double closest = 1e9;
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_LT(box.signed_distance(pts[i]), 0.0);
    for (size_t j = i + 1; j < pts.size(); ++j) closest = std::min(closest, (pts[i] - pts[j]).norm());
  }
  EXPECT_GE(closest, h);
  // Maximal Poisson-disk packings reach roughly 0.6-0.75 points per h^3 of volume.
  const double per_h3 = static_cast<double>(pts.size()) / (0.2 * 0.1 * 0.1 / (h * h * h));
  EXPECT_GT(per_h3, 0.4);
  EXPECT_LT(per_h3, 1.0);
  // Deterministic for a seed.
  EXPECT_EQ(pts, sample_poisson_disk(box, Vec3(-0.1, -0.05, -0.05), Vec3(0.1, 0.05, 0.05), h, 3));
}

TEST(SolidParticles, MlsForceFormIsConsistent) {
  // One stressed particle: the node forces sum to zero and their first moment is -S (both the MLS-MPM
  // form of thesis Eq. 2.24 and the gradient form of Eq. 2.17 satisfy sum_i f_i x_i^T = -S).
  SolidParticles s;
  s.material = {1e5, 2e5, 1000};
  s.add({Vec3(0.123, 0.456, 0.789)}, 0.01, Vec3::Zero());
  s.F[0] << 1.1, 0.05, 0.0, -0.02, 0.95, 0.03, 0.01, 0.0, 1.02;
  ASSERT_EQ(s.compute_stress(), 1u);
  for (bool mls : {true, false}) {
    ParticleSet view = s.view();
    view.mls_force = mls;
    SparseGrid g(0.05);
    g.rebuild({view});
    g.transfer_forces({view});
    Vec3 sum = Vec3::Zero();
    Mat3 moment = Mat3::Zero();
    for (size_t n = 0; n < g.num_nodes(); ++n) {
      sum += g.node_force(n);
      moment += g.node_force(n) * g.node_position(n).transpose();
    }
    EXPECT_LE(sum.norm(), 1e-12 * s.stress[0].norm() / 0.05);
    EXPECT_LE((moment + s.stress[0]).norm(), 1e-10 * s.stress[0].norm());
  }
  // V^0 P F^T = V^0 (mu (F F^T - I) + lambda ln J I)
  const Mat3& F = s.F[0];
  const Mat3 expected = 1e-6 * (1e5 * (F * F.transpose() - Mat3::Identity()) + 2e5 * std::log(F.determinant()) * Mat3::Identity());
  EXPECT_LE((s.stress[0] - expected).norm(), 1e-12 * expected.norm());
}

TEST(SolidParticles, InvertedParticleIsReported) {
  SolidParticles s;
  s.material = {1e5, 2e5, 1000};
  s.add({Vec3(0, 0, 0), Vec3(0.01, 0, 0)}, 0.01, Vec3::Zero());
  s.F[1](2, 2) = -1;
  EXPECT_EQ(s.compute_stress(), 1u);
}

}  // namespace
}  // namespace shellfrac::mpm
