#include "mpm/colliders.hpp"

#include <gtest/gtest.h>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

TEST(Shapes, SignedDistancesAndNormals) {
  const HalfSpace ground(Vec3(0, 0.5, 0), Vec3(0, 2, 0));
  EXPECT_DOUBLE_EQ(ground.signed_distance(Vec3(3, 1.5, -2)), 1.0);
  EXPECT_DOUBLE_EQ(ground.signed_distance(Vec3(0, 0.25, 0)), -0.25);
  const Sphere ball(Vec3(1, 0, 0), 0.5);
  EXPECT_DOUBLE_EQ(ball.signed_distance(Vec3(1, 2, 0)), 1.5);
  EXPECT_DOUBLE_EQ(ball.signed_distance(Vec3(1.25, 0, 0)), -0.25);
  EXPECT_LE((ball.normal(Vec3(1, 0, 3)) - Vec3(0, 0, 1)).norm(), 1e-15);
  const Box box(Vec3(0, 0, 0), Vec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(box.signed_distance(Vec3(2, 0, 0)), 1.0);
  EXPECT_DOUBLE_EQ(box.signed_distance(Vec3(2, 3, 0)), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(box.signed_distance(Vec3(0.5, 0, 0)), -0.5);
  EXPECT_LE((box.normal(Vec3(0.9, 0.1, 0.1)) - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_LE((box.normal(Vec3(0, 0, -5)) - Vec3(0, 0, -1)).norm(), 1e-15);
}

TEST(Boundary, StickySlipAndCoulombFriction) {
  const Vec3 n(0, 1, 0), vc(0.5, 0, 0);
  const Vec3 v(2.5, -1, 0);  // relative: (2, -1, 0), approaching
  EXPECT_EQ(collide_velocity(v, vc, n, Boundary::Sticky, 0.3), vc);
  EXPECT_LE((collide_velocity(v, vc, n, Boundary::Slip, 0.3) - Vec3(2.5, 0, 0)).norm(), 1e-15);
  // Coulomb: tangential relative speed 2 drops by mu * 1 = 0.3.
  EXPECT_LE((collide_velocity(v, vc, n, Boundary::Friction, 0.3) - Vec3(0.5 + 1.7, 0, 0)).norm(), 1e-15);
  // Friction strong enough to stop the sliding.
  EXPECT_LE((collide_velocity(v, vc, n, Boundary::Friction, 5.0) - vc).norm(), 1e-15);
  // Separating material is left alone.
  const Vec3 away(1, 2, 0);
  EXPECT_EQ(collide_velocity(away, vc, n, Boundary::Friction, 0.3), away);
}

TEST(RigidMotion, ConstantAndKeyframedMotion) {
  RigidMotion m;
  m.pivot = Vec3(1, 0, 0);
  m.linear_velocity = Vec3(0, 2, 0);
  m.angular_velocity = Vec3(0, 0, 1);
  // The pivot translates; a point at distance 1 from it also rotates.
  EXPECT_LE((m.pose(0.5) * Vec3(1, 0, 0) - Vec3(1, 1, 0)).norm(), 1e-15);
  EXPECT_LE((m.velocity_at(Vec3(2, 1, 0), 0.5) - Vec3(0, 3, 0)).norm(), 1e-15);
  RigidMotion k;
  k.keyframes = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3(2, 0, 0), Vec3::Zero()}};
  EXPECT_LE((k.pose(0.25) * Vec3::Zero() - Vec3(0.5, 0, 0)).norm(), 1e-15);
  EXPECT_LE((k.velocity_at(Vec3(3, 3, 3), 0.5) - Vec3(2, 0, 0)).norm(), 1e-6);
  EXPECT_LE((k.pose(7.0) * Vec3::Zero() - Vec3(2, 0, 0)).norm(), 1e-15);  // holds the last pose
}

TEST(Colliders, GridNodesInsideAreProjected) {
  std::vector<Vec3> x{Vec3(0.5, 0.02, 0.5)}, v{Vec3(1, -3, 0)};
  std::vector<double> m{1.0};
  ParticleSet s;
  s.count = 1;
  s.position = x.data();
  s.velocity = v.data();
  s.mass = m.data();
  SparseGrid g(0.1);
  g.rebuild({s});
  g.transfer_mass_momentum({s});
  g.update_velocities(0.0, Vec3::Zero());
  Collider ground;
  ground.shape = std::make_shared<HalfSpace>(Vec3::Zero(), Vec3(0, 1, 0));
  ground.boundary = Boundary::Slip;
  apply_colliders(g, {ground}, 0.0);
  for (size_t n = 0; n < g.num_nodes(); ++n) {
    if (g.node_mass(n) <= 0) continue;
    const Vec3 xi = g.node_position(n);
    if (xi.y() <= 0)
      EXPECT_GE(g.node_velocity(n).y(), 0.0);  // no approach into the ground
    else
      EXPECT_DOUBLE_EQ(g.node_velocity(n).y(), -3.0);
  }
}

}  // namespace
}  // namespace shellfrac::mpm
