#include "mpm/sparse_grid.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <tbb/global_control.h>

#include <random>
#include <tuple>

namespace shellfrac::mpm {
namespace {

struct Particles {
  std::vector<Vec3> x, v, f;
  std::vector<double> m;
  std::vector<Mat3> C, S, grad;
  ParticleSet set(bool apic) {
    ParticleSet s;
    s.count = x.size();
    s.position = x.data();
    s.velocity = v.data();
    s.mass = m.data();
    s.force = f.data();
    s.stress = S.data();
    s.affine = apic ? C.data() : nullptr;
    s.velocity_gradient = grad.data();
    return s;
  }
};

Particles random_particles(size_t n, unsigned seed, Vec3 origin = Vec3::Zero(), double extent = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), s(-1, 1);
  Particles p;
  for (size_t i = 0; i < n; ++i) {
    p.x.push_back(origin + extent * Vec3(u(rng), u(rng), u(rng)));
    p.v.push_back(Vec3(s(rng), s(rng), s(rng)));
    p.f.push_back(Vec3(s(rng), s(rng), s(rng)));
    p.m.push_back(0.5 + u(rng));
    Mat3 c, st;
    for (int k = 0; k < 9; ++k) c(k / 3, k % 3) = s(rng);
    for (int k = 0; k < 9; ++k) st(k / 3, k % 3) = s(rng);
    p.C.push_back(c);
    p.S.push_back(st);
    p.grad.push_back(Mat3::Zero());
  }
  return p;
}

// rebuild() keeps a block layout while it holds every particle's stencil (SparseGrid::set_layout_reuse):
// 60 steps of a cloud that flies through many blocks (each particle crosses about 6 cells) give the same
// bits with the layout built afresh every step and with the default reuse, which keeps it for up to 16.
TEST(SparseGrid, KeptLayoutGivesTheSameBitsAsAFreshOne) {
  Particles fresh = random_particles(3000, 11, Vec3(0.2, 0.3, 0.1), 0.5);
  Particles kept = fresh;
  SparseGrid a(0.05), b(0.05);
  a.set_layout_reuse(0);
  ASSERT_GT(SparseGrid::kDefaultLayoutReuse, 1);
  for (int step = 0; step < 60; ++step)
    for (auto [grid, p] : {std::pair<SparseGrid*, Particles*>{&a, &fresh}, {&b, &kept}}) {
      std::vector<ParticleSet> sets{p->set(true)};
      grid->rebuild(sets);
      grid->transfer_mass_momentum(sets);
      grid->transfer_forces(sets);
      grid->update_velocities(1e-3, Vec3(0, -9.81, 0));
      grid->transfer_to_particles(sets, 5e-3);
      for (size_t i = 0; i < p->x.size(); ++i) p->x[i] += 5e-3 * p->v[i];  // about 0.1 cell per step
    }
  size_t differ = 0;
  for (size_t i = 0; i < fresh.x.size(); ++i)
    differ += fresh.x[i] != kept.x[i] || fresh.v[i] != kept.v[i] || fresh.C[i] != kept.C[i] || fresh.grad[i] != kept.grad[i];
  EXPECT_EQ(differ, 0u);
}

// The same with slow particles in two sets, as a sheet's control points and shear particles move: on
// some steps nobody changes block and the bins and entry order are kept; on others a few particles cross
// a block border and are binned again; halfway the second set loses particles, which bins all afresh.
// Every step's particles equal those of a layout built afresh, bit for bit.
TEST(SparseGrid, RefreshedBinsGiveTheSameBitsAsAFreshLayout) {
  Particles fresh_a = random_particles(300, 21, Vec3(0.2, 0.3, 0.1), 0.5);
  Particles fresh_b = random_particles(200, 22, Vec3(0.25, 0.2, 0.1), 0.5);
  Particles kept_a = fresh_a, kept_b = fresh_b;
  SparseGrid a(0.05), b(0.05);
  a.set_layout_reuse(0);
  for (int step = 0; step < 80; ++step) {
    if (step == 40)
      for (Particles* p : {&fresh_b, &kept_b}) {
        p->x.resize(150);
        p->v.resize(150);
      }
    for (auto [grid, pa, pb] : {std::tuple<SparseGrid*, Particles*, Particles*>{&a, &fresh_a, &fresh_b},
                                {&b, &kept_a, &kept_b}}) {
      std::vector<ParticleSet> sets{pa->set(true), pb->set(false)};
      grid->rebuild(sets);
      grid->transfer_mass_momentum(sets);
      grid->transfer_forces(sets);
      grid->update_velocities(1e-3, Vec3(0, -9.81, 0));
      grid->transfer_to_particles(sets, 5e-5);
      for (Particles* p : {pa, pb})
        for (size_t i = 0; i < p->x.size(); ++i) p->x[i] += 5e-5 * p->v[i];  // at most 0.002 cells per step
    }
  }
  // Each path ran: kept bins, particles binned again on the kept layout, and fresh layouts (the first
  // step, every kDefaultLayoutReuse + 1 steps, and the step the set shrank).
  const SparseGrid::RebuildCounts& c = b.rebuild_counts();
  EXPECT_GT(c.kept_bins, 10u);
  EXPECT_GT(c.rebinned, 5u);
  EXPECT_GE(c.fresh_layouts, 80u / (SparseGrid::kDefaultLayoutReuse + 1));
  EXPECT_EQ(c.kept_bins + c.rebinned + c.fresh_layouts + c.kept_layout_rebinned_afresh, 80u);
  EXPECT_EQ(a.rebuild_counts().fresh_layouts, 80u);
  size_t differ = 0;
  for (auto [f, k] : {std::pair<Particles*, Particles*>{&fresh_a, &kept_a}, {&fresh_b, &kept_b}})
    for (size_t i = 0; i < f->x.size(); ++i) differ += f->x[i] != k->x[i] || f->v[i] != k->v[i] || f->grad[i] != k->grad[i];
  EXPECT_EQ(differ, 0u);
}

TEST(SparseGrid, TransfersConserveMassMomentumAndForce) {
  Particles p = random_particles(500, 1);
  for (bool apic : {false, true}) {
    SparseGrid g(0.05);
    std::vector<ParticleSet> sets{p.set(apic)};
    g.rebuild(sets);
    g.transfer_mass_momentum(sets);
    g.transfer_forces(sets);
    double m_grid = 0, m_part = 0;
    Vec3 p_grid = Vec3::Zero(), p_part = Vec3::Zero(), f_grid = Vec3::Zero(), f_part = Vec3::Zero();
    for (size_t n = 0; n < g.num_nodes(); ++n) {
      m_grid += g.node_mass(n);
      p_grid += g.node_momentum(n);
      f_grid += g.node_force(n);
    }
    for (size_t i = 0; i < p.x.size(); ++i) {
      m_part += p.m[i];
      p_part += p.m[i] * p.v[i];
      f_part += p.f[i];  // stress terms sum to zero: sum_i grad w_ip = 0
    }
    EXPECT_NEAR(m_grid, m_part, 1e-12 * m_part);
    EXPECT_LE((p_grid - p_part).norm(), 1e-12 * m_part);
    EXPECT_LE((f_grid - f_part).norm(), 1e-10 * static_cast<double>(p.x.size()));
  }
}

TEST(SparseGrid, LinearVelocityFieldIsReproducedExactly) {
  // Grid velocities sampled from v(x) = b + A x: PIC gathers v(x_p) exactly, the velocity gradient is A,
  // and APIC's affine C_p equals A (quadratic B-splines reproduce linear fields).
  Particles p = random_particles(200, 2, Vec3(0.3, -0.2, 0.1), 0.5);
  SparseGrid g(0.04);
  std::vector<ParticleSet> sets{p.set(true)};
  g.rebuild(sets);
  g.transfer_mass_momentum(sets);
  Mat3 A;
  A << 0.1, -0.4, 0.3, 0.2, 0.0, -0.1, 0.5, 0.25, -0.2;
  const Vec3 b(1, 2, 3);
  for (size_t n = 0; n < g.num_nodes(); ++n) g.node_velocity(n) = b + A * g.node_position(n);
  g.transfer_to_particles(sets);
  for (size_t i = 0; i < p.x.size(); ++i) {
    EXPECT_LE((p.v[i] - (b + A * p.x[i])).norm(), 1e-12);
    EXPECT_LE((p.grad[i] - A).norm(), 1e-11);
    EXPECT_LE((p.C[i] - A).norm(), 1e-11);
  }
}

TEST(SparseGrid, RigidAffineKeepsRotationAndDropsStretch) {
  // RPIC (ParticleSet::rigid_affine): g2p keeps the skew part of C_p. For v(x) = b + (W + S) x, W skew and
  // S symmetric, C_p = W exactly; with only W, a p2g-g2p round trip of the rigid field returns every
  // particle's velocity and C_p (quadratic B-splines reproduce linear fields), and p2g carries the
  // particles' angular momentum sum x m v + m (C D) terms to the grid unchanged.
  Particles p = random_particles(200, 4, Vec3(0.3, -0.2, 0.1), 0.5);
  SparseGrid g(0.04);
  ParticleSet set = p.set(true);
  set.rigid_affine = true;
  std::vector<ParticleSet> sets{set};
  g.rebuild(sets);
  g.transfer_mass_momentum(sets);
  Mat3 W, S;
  W << 0, -0.4, 0.3, 0.4, 0, -0.1, -0.3, 0.1, 0;
  S << 0.2, 0.1, -0.05, 0.1, -0.3, 0.15, -0.05, 0.15, 0.1;
  const Vec3 b(1, 2, 3);
  for (size_t n = 0; n < g.num_nodes(); ++n) g.node_velocity(n) = b + (W + S) * g.node_position(n);
  g.transfer_to_particles(sets);
  for (size_t i = 0; i < p.x.size(); ++i) {
    EXPECT_LE((p.v[i] - (b + (W + S) * p.x[i])).norm(), 1e-12);
    EXPECT_LE((p.C[i] - W).norm(), 1e-11);
  }
  // Rigid field on the particles: p2g then g2p gives it back.
  for (size_t i = 0; i < p.x.size(); ++i) {
    p.v[i] = b + W * p.x[i];
    p.C[i] = W;
  }
  SparseGrid h(0.04);
  h.rebuild(sets);
  h.transfer_mass_momentum(sets);
  Vec3 grid_l = Vec3::Zero();
  for (size_t n = 0; n < h.num_nodes(); ++n) grid_l += h.node_position(n).cross(h.node_momentum(n));
  Vec3 particle_l = Vec3::Zero();
  const double d = 0.25 * 0.04 * 0.04;  // D_p = dx^2 / 4 I for quadratic B-splines
  for (size_t i = 0; i < p.x.size(); ++i) {
    particle_l += p.m[i] * p.x[i].cross(p.v[i]);
    const Mat3 K = p.m[i] * d * p.C[i].transpose();  // angular momentum of the affine part: eps : (m C D)^T
    particle_l += Vec3(K(1, 2) - K(2, 1), K(2, 0) - K(0, 2), K(0, 1) - K(1, 0));
  }
  EXPECT_LE((grid_l - particle_l).norm(), 1e-12 * particle_l.norm());
  for (size_t n = 0; n < h.num_nodes(); ++n)
    if (h.node_mass(n) > 0) h.node_velocity(n) = h.node_momentum(n) / h.node_mass(n);
  h.transfer_to_particles(sets);
  for (size_t i = 0; i < p.x.size(); ++i) {
    EXPECT_LE((p.v[i] - (b + W * p.x[i])).norm(), 1e-12);
    EXPECT_LE((p.C[i] - W).norm(), 1e-11);
  }
}

TEST(SparseGrid, ResultsAreIdenticalForAnyThreadCount) {
  Particles p = random_particles(3000, 3, Vec3(-1, -1, -1), 2.0);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    SparseGrid g(0.07);
    std::vector<ParticleSet> sets{p.set(true)};
    g.rebuild(sets);
    g.transfer_mass_momentum(sets);
    g.transfer_forces(sets);
    std::vector<double> out;
    for (size_t n = 0; n < g.num_nodes(); ++n) {
      out.push_back(g.node_mass(n));
      for (int c = 0; c < 3; ++c) out.push_back(g.node_momentum(n)[c]);
      for (int c = 0; c < 3; ++c) out.push_back(g.node_force(n)[c]);
    }
    return out;
  };
  const auto one = run(1), two = run(2), four = run(4);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_TRUE(one == two);  // bit-identical
  EXPECT_TRUE(one == four);
}

TEST(SparseGrid, MemoryFollowsParticles) {
  // Two small clusters 10 m apart with dx = 1 cm: a dense box would need ~1e9 nodes.
  Particles a = random_particles(100, 4, Vec3(0, 0, 0), 0.05);
  Particles b = random_particles(100, 5, Vec3(10, 10, 10), 0.05);
  SparseGrid g(0.01);
  std::vector<ParticleSet> sets{a.set(false), b.set(false)};
  g.rebuild(sets);
  EXPECT_LE(g.num_nodes(), 2u * 64u * 64u);  // a few blocks per cluster
  EXPECT_GE(g.node_index(0, 0, 0), 0);
  EXPECT_EQ(g.node_index(500, 500, 500), -1);
  g.transfer_mass_momentum(sets);
  double m = 0;
  for (size_t n = 0; n < g.num_nodes(); ++n) m += g.node_mass(n);
  double expected = 0;
  for (double x : a.m) expected += x;
  for (double x : b.m) expected += x;
  EXPECT_NEAR(m, expected, 1e-12 * expected);
}

TEST(SparseGrid, VelocityUpdateAndNonFinitePositions) {
  Particles p = random_particles(50, 6);
  for (auto& f : p.f) f.setZero();
  for (auto& s : p.S) s.setZero();
  SparseGrid g(0.1);
  std::vector<ParticleSet> sets{p.set(false)};
  g.rebuild(sets);
  g.transfer_mass_momentum(sets);
  g.transfer_forces(sets);
  const Vec3 gravity(0, -9.81, 0);
  g.update_velocities(0.01, gravity);
  // Momentum after the update: sum m_i v_i = sum m_p v_p + dt M g.
  Vec3 P = Vec3::Zero(), expected = Vec3::Zero();
  double M = 0;
  for (size_t n = 0; n < g.num_nodes(); ++n) P += g.node_mass(n) * g.node_velocity(n);
  for (size_t i = 0; i < p.x.size(); ++i) {
    expected += p.m[i] * p.v[i];
    M += p.m[i];
  }
  expected += 0.01 * M * gravity;
  EXPECT_LE((P - expected).norm(), 1e-12 * M);
  p.x[7].x() = std::numeric_limits<double>::quiet_NaN();
  try {
    g.rebuild(sets);
    FAIL();
  } catch (const GridError& e) {
    EXPECT_EQ(e.set(), 0u);
    EXPECT_EQ(e.particle(), 7u);
  }
}

}  // namespace
}  // namespace shellfrac::mpm
