// The FLIP blend of g2p (mpm/particle_set.hpp): with no forces the grid's velocity change is zero, so
// FLIP share 1 gives every particle its own velocity back exactly, PIC smooths it, and any share keeps
// the total momentum of the forced update.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include <Eigen/Geometry>

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

void step(Cloud& c, double flip, bool affine, double dt, const double* shares = nullptr) {
  SparseGrid g(0.1);
  std::vector<ParticleSet> sets{c.set(flip, affine)};
  sets[0].flip_share = shares;
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

TEST(FlipTransfer, MixedSharesKeepTheMomentumOfTheForcedUpdate) {
  // Per-particle shares (the adaptive transfer): half the particles at 1, the rest at 0 or 0.5. Without the
  // mean-residual correction of g2p the momentum would be off by sum_p m_p r_p delta_p, which on this random
  // field is of order 1 (checked below), so the 1e-12 bound can only hold through the correction.
  for (double low : {0.0, 0.5})
    for (bool affine : {false, true}) {
      Cloud c = cloud(7);
      std::vector<double> shares(c.x.size());
      for (size_t i = 0; i < shares.size(); ++i) shares[i] = c.x[i].x() < 0.5 ? low : 1.0;
      Vec3 f = Vec3::Zero();
      for (const Vec3& fi : c.f) f += fi;
      const Vec3 expected = momentum(c) + 0.01 * f;
      const std::vector<Vec3> before = c.v;
      step(c, 0.0, affine, 0.01, shares.data());
      EXPECT_LE((momentum(c) - expected).norm(), 1e-12 * 400) << "low " << low << " affine " << affine;
      // The particles at share 1 keep their own velocity up to the grid's change and the small common
      // correction: far from PIC's smoothing of the random field.
      Cloud pic = cloud(7);
      step(pic, 0.0, affine, 0.01);
      double kept = 0, smoothed = 0;
      for (size_t i = 0; i < c.v.size(); ++i)
        if (shares[i] == 1.0) {
          kept = std::max(kept, (c.v[i] - before[i]).norm());
          smoothed = std::max(smoothed, (pic.v[i] - before[i]).norm());
        }
      EXPECT_LT(kept, 0.2 * smoothed) << "low " << low;
    }
}

// Angular momentum about the origin of a cloud carried by APIC/affine-FLIP on quadratic B-splines:
// sum_p m_p x_p x v_p plus what each affine velocity carries, m_p (dx^2 / 4) times the axial vector of C_p
// (Jiang et al. 2015).
Vec3 angular_momentum(const Cloud& c, double dx) {
  const double d = 0.25 * dx * dx;
  Vec3 L = Vec3::Zero();
  for (size_t i = 0; i < c.x.size(); ++i) {
    const Mat3& C = c.C[i];
    L += c.m[i] * c.x[i].cross(c.v[i]) + c.m[i] * d * Vec3(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
  }
  return L;
}

TEST(FlipTransfer, MixedSharesKeepAngularMomentumThroughTheStep) {
  // Shares 0 and 1 (the adaptive transfer's values), no forces: p2g, grid update, g2p, then the advection
  // with the grid's velocity (v_p minus its FLIP part), three times. APIC alone keeps angular momentum
  // exactly through this; the FLIP parts of the share-1 particles carry some that the grid never saw,
  // which the rotation added to the share-0 particles in g2p gives back. Criterion: 1e-12 relative.
  Cloud c = cloud(7);
  for (size_t i = 0; i < c.x.size(); ++i) c.v[i] += Vec3(0, 0, 3).cross(c.x[i] - Vec3(0.5, 0.5, 0));  // a spin
  std::vector<double> shares(c.x.size());
  for (size_t i = 0; i < shares.size(); ++i) shares[i] = c.x[i].x() < 0.5 ? 0.0 : 1.0;
  std::vector<Vec3> flip_part(c.x.size(), Vec3::Zero());
  const double dx = 0.1, dt = 0.01;
  const Vec3 before = angular_momentum(c, dx);
  Vec3 uncorrected = Vec3::Zero();  // the FLIP parts' own angular momentum at the advected positions
  for (int n = 0; n < 3; ++n) {
    SparseGrid g(dx);
    std::vector<ParticleSet> sets{c.set(0.0, true)};
    sets[0].flip_share = shares.data();
    sets[0].flip_part = flip_part.data();
    sets[0].force = nullptr;
    g.rebuild(sets);
    g.transfer_mass_momentum(sets);
    g.update_velocities(dt, Vec3::Zero());
    g.transfer_to_particles(sets, dt);
    for (size_t i = 0; i < c.x.size(); ++i) {
      c.x[i] += dt * (c.v[i] - flip_part[i]);
      uncorrected += c.m[i] * c.x[i].cross(flip_part[i]);
    }
  }
  const Vec3 after = angular_momentum(c, dx);
  std::printf("mixed shares 0/1, three steps: |dL| / |L| %.3g; the FLIP parts alone carry %.3g of |L|\n",
              (after - before).norm() / before.norm(), uncorrected.norm() / before.norm());
  EXPECT_LE((after - before).norm(), 1e-12 * before.norm());
  EXPECT_GT(uncorrected.norm(), 1e-3 * before.norm());  // what the correction has to give back is not small
}

TEST(FlipTransfer, UncorrectedMixedSharesWouldLoseMomentum) {
  // The size of what the correction restores: sum_p m_p r_p delta_p with delta_p = v_p - sum_i w_ip v_i^old,
  // computed here from a share-0 and a share-1 g2p of the same field with no forces (delta = v_FLIP - v_PIC).
  Cloud flip = cloud(7), pic = cloud(7);
  step(flip, 1.0, false, 0.0);
  step(pic, 0.0, false, 0.0);
  Vec3 defect = Vec3::Zero();
  for (size_t i = 0; i < flip.x.size(); ++i)
    if (flip.x[i].x() < 0.5) defect += flip.m[i] * (flip.v[i] - pic.v[i]);
  EXPECT_GT(defect.norm(), 1.0);  // the momentum half a FLIP cloud would lose without the correction
}

}  // namespace
}  // namespace shellfrac::mpm
