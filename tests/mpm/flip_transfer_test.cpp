// The FLIP blend of g2p (mpm/particle_set.hpp): with no forces the grid's velocity change is zero, so
// FLIP share 1 gives every particle its own velocity back exactly, PIC smooths it, and any share keeps
// the total momentum of the forced update.
#include <gtest/gtest.h>

#include <random>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

struct Cloud {
  std::vector<Vec3> x, v, f;
  std::vector<double> m;
  std::vector<Mat3> C;
  ParticleSet set(double flip, bool affine) {
    ParticleSet s;
    s.count = x.size();
    s.position = x.data();
    s.velocity = v.data();
    s.mass = m.data();
    s.force = f.data();
    s.affine = affine ? C.data() : nullptr;
    s.flip = flip;
    return s;
  }
};

Cloud cloud(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), s(-1, 1);
  Cloud c;
  for (int i = 0; i < 400; ++i) {
    c.x.push_back(Vec3(u(rng), u(rng), 0.1 * u(rng)));
    c.v.push_back(Vec3(s(rng), s(rng), s(rng)));
    c.f.push_back(Vec3(s(rng), s(rng), s(rng)));
    c.m.push_back(0.5 + u(rng));
    c.C.push_back(Mat3::Zero());
  }
  return c;
}

Vec3 momentum(const Cloud& c) {
  Vec3 p = Vec3::Zero();
  for (size_t i = 0; i < c.x.size(); ++i) p += c.m[i] * c.v[i];
  return p;
}

void step(Cloud& c, double flip, bool affine, double dt) {
  SparseGrid g(0.1);
  std::vector<ParticleSet> sets{c.set(flip, affine)};
  g.rebuild(sets);
  g.transfer_mass_momentum(sets);
  g.transfer_forces(sets);
  g.update_velocities(dt, Vec3::Zero());
  g.transfer_to_particles(sets);
}

TEST(FlipTransfer, FullFlipReturnsTheParticleVelocityWhenTheGridDoesNotChange) {
  for (bool affine : {false, true}) {
    Cloud c = cloud(3);
    const std::vector<Vec3> before = c.v;
    step(c, 1.0, affine, 0.0);
    double worst = 0, pic_change = 0;
    for (size_t i = 0; i < c.v.size(); ++i) worst = std::max(worst, (c.v[i] - before[i]).norm());
    EXPECT_LE(worst, 1e-12);  // round-off of v_PIC - sum w v_old
    Cloud pic = cloud(3);
    step(pic, 0.0, affine, 0.0);
    for (size_t i = 0; i < pic.v.size(); ++i) pic_change = std::max(pic_change, (pic.v[i] - before[i]).norm());
    EXPECT_GT(pic_change, 0.1);  // PIC replaces the random field by its smooth projection
  }
}

TEST(FlipTransfer, AnyShareKeepsTheMomentumOfTheForcedUpdate) {
  // sum_p m_p v_p after g2p = sum_p m_p v_p before + dt sum_p f_p, for PIC, FLIP and blends.
  for (double flip : {0.0, 0.5, 0.99, 1.0})
    for (bool affine : {false, true}) {
      Cloud c = cloud(5);
      Vec3 f = Vec3::Zero();
      for (const Vec3& fi : c.f) f += fi;
      const Vec3 expected = momentum(c) + 0.01 * f;
      step(c, flip, affine, 0.01);
      EXPECT_LE((momentum(c) - expected).norm(), 1e-12 * 400) << "flip " << flip << " affine " << affine;
    }
}

}  // namespace
}  // namespace shellfrac::mpm
