// Phantom copies of grid nodes and the contact between them (thesis sec. 4.7, Eq. 4.22-4.26).
#include "mpm/phantom_nodes.hpp"

#include <gtest/gtest.h>

#include <random>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

constexpr double kDx = 0.1;

// Particles on a jittered lattice in a slab; `side` says which fragment each belongs to.
struct Fragments {
  std::vector<Vec3> x, v;
  std::vector<double> m;
  std::vector<int> side;
  std::vector<unsigned char> near;
  ParticleSet set() {
    ParticleSet s;
    s.count = x.size();
    s.position = x.data();
    s.velocity = v.data();
    s.mass = m.data();
    return s;
  }
  void add(const Vec3& p, const Vec3& vel, int sd, double mass = 1.0) {
    x.push_back(p);
    v.push_back(vel);
    m.push_back(mass);
    side.push_back(sd);
    near.push_back(1);
  }
};

// Two sheets of particles meeting at the plane x = 0.5 (a crack), moving with va and vb.
Fragments two_fragments(const Vec3& va, const Vec3& vb) {
  Fragments f;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> j(-0.001, 0.001);  // slight jitter: normals stay within 1 degree of x
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k) {
      const double y = 0.3 + 0.04 * k;
      const double xa = 0.5 - 0.02 - 0.04 * i, xb = 0.5 + 0.02 + 0.04 * i;
      f.add(Vec3(xa, y, 0.5 + j(rng)), va, 0, 1.0 + 0.1 * i);
      f.add(Vec3(xb, y, 0.5 + j(rng)), vb, 1, 0.7 + 0.05 * i);
    }
  return f;
}

Vec3 grid_momentum(const SparseGrid& g) {
  Vec3 p = Vec3::Zero();
  for (size_t n = 0; n < g.num_nodes(); ++n) p += g.node_mass(n) * g.node_velocity(n);
  return p;
}

double grid_mass(const SparseGrid& g) {
  double m = 0;
  for (size_t n = 0; n < g.num_nodes(); ++n) m += g.node_mass(n);
  return m;
}

struct Prepared {
  SparseGrid grid{kDx};
  PhantomLayout layout;
};

void prepare(Prepared& pr, Fragments& f, const Connectivity& connected, FieldKind kind = FieldKind::Shell) {
  std::vector<ParticleSet> sets{f.set()};
  pr.grid.rebuild(sets);
  pr.layout = partition_nodes(pr.grid, sets, {PartitionRole{kind, f.near.data()}}, connected);
  pr.grid.set_phantom_copies(pr.layout);
  pr.grid.transfer_mass_momentum(sets);
  pr.grid.update_velocities(1e-3, Vec3::Zero());
}

TEST(PhantomNodes, OneCopyPerFragmentSideAndMassConserved) {
  Fragments f = two_fragments(Vec3::Zero(), Vec3::Zero());
  Prepared pr;
  prepare(pr, f, [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return f.side[a] == f.side[b]; });
  EXPECT_GT(pr.layout.split_nodes, 10u);
  EXPECT_EQ(pr.layout.copy_parent.size(), 2 * pr.layout.split_nodes);
  double total = 0;
  for (double m : f.m) total += m;
  EXPECT_NEAR(grid_mass(pr.grid), total, 1e-12 * total);
  // Split grid nodes keep no mass of their own: everything went to the copies.
  for (uint32_t node : pr.layout.copy_parent) EXPECT_EQ(pr.grid.node_mass(node), 0.0);
}

TEST(PhantomNodes, ConnectedParticlesMakeNoCopies) {
  Fragments f = two_fragments(Vec3::Zero(), Vec3::Zero());
  Prepared pr;
  prepare(pr, f, [](uint32_t, uint32_t, uint32_t, uint32_t) { return true; });
  EXPECT_EQ(pr.layout.split_nodes, 0u);
  EXPECT_EQ(pr.grid.num_phantom_copies(), 0u);
}

TEST(PhantomNodes, ApproachingFragmentsStopWithMomentumConserved) {
  // Fragment 0 (x < 0.5) moves +x into fragment 1, which moves -x; plus a tangential slip along y.
  Fragments f = two_fragments(Vec3(1.0, 0.3, 0.0), Vec3(-0.5, -0.2, 0.0));
  Prepared pr;
  prepare(pr, f, [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return f.side[a] == f.side[b]; });
  const Vec3 before = grid_momentum(pr.grid);
  const ContactStats st = resolve_phantom_contact(pr.grid, pr.layout.copy_kind, 1e-3, 0.0);
  const Vec3 after = grid_momentum(pr.grid);
  EXPECT_EQ(st.nodes, pr.layout.split_nodes);
  EXPECT_GT(st.pairs_resolved, 0u);
  EXPECT_LE((after - before).norm(), 1e-13 * before.norm());  // Eq. 4.26: equal and opposite
  // No copy pair still approaches along its normal (shell-shell: between the centres of mass).
  const size_t g = pr.grid.num_grid_nodes();
  for (size_t c = 0; c + 1 < pr.grid.num_phantom_copies(); c += 2) {
    const Vec3 ca = pr.grid.copy_mass_position(c) / pr.grid.node_mass(g + c);
    const Vec3 cb = pr.grid.copy_mass_position(c + 1) / pr.grid.node_mass(g + c + 1);
    const Vec3 n = (cb - ca).normalized();
    EXPECT_LE((pr.grid.node_velocity(g + c) - pr.grid.node_velocity(g + c + 1)).dot(n), 1e-4);
    // Frictionless: the tangential slip along y survives the contact untouched (interior nodes, where
    // the centres of mass differ along x only; at the sheet's rim they also differ along y).
    if (std::abs(pr.grid.node_position(g + c).y() - 0.48) > 0.1) continue;
    EXPECT_NEAR(pr.grid.node_velocity(g + c).y() - pr.grid.node_velocity(g + c + 1).y(), 0.5, 0.05);
  }
}

TEST(PhantomNodes, SeparatingFragmentsAreLeftAlone) {
  Fragments f = two_fragments(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0));
  Prepared pr;
  prepare(pr, f, [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return f.side[a] == f.side[b]; });
  std::vector<Vec3> v0;
  for (size_t n = 0; n < pr.grid.num_nodes(); ++n) v0.push_back(pr.grid.node_velocity(n));
  const ContactStats st = resolve_phantom_contact(pr.grid, pr.layout.copy_kind, 1e-3, 0.5);
  EXPECT_EQ(st.pairs_resolved, 0u);
  for (size_t n = 0; n < pr.grid.num_nodes(); ++n) EXPECT_EQ(pr.grid.node_velocity(n), v0[n]);
}

TEST(PhantomNodes, StickingFrictionRemovesTheTangentialSlip) {
  // Pressing together (normal approach 1 m/s) with a 0.1 m/s slip: mu = 1 gives |f_T| <= mu |f_N|, so
  // the copies stick (Eq. 4.24); mu = 0.05 caps the tangential force at the Coulomb limit (Eq. 4.25),
  // which removes mu x (normal velocity change) = 0.05 m/s of the slip. Interior nodes only (see above).
  for (double mu : {1.0, 0.05}) {
    Fragments f = two_fragments(Vec3(0.5, 0.05, 0.0), Vec3(-0.5, -0.05, 0.0));
    Prepared pr;
    prepare(pr, f, [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return f.side[a] == f.side[b]; });
    std::vector<double> slip0;
    const size_t g = pr.grid.num_grid_nodes();
    for (size_t c = 0; c + 1 < pr.grid.num_phantom_copies(); c += 2)
      slip0.push_back(pr.grid.node_velocity(g + c).y() - pr.grid.node_velocity(g + c + 1).y());
    resolve_phantom_contact(pr.grid, pr.layout.copy_kind, 1e-3, mu);
    for (size_t c = 0, k = 0; c + 1 < pr.grid.num_phantom_copies(); c += 2, ++k) {
      if (std::abs(pr.grid.node_position(g + c).y() - 0.48) > 0.1) continue;
      const double slip = pr.grid.node_velocity(g + c).y() - pr.grid.node_velocity(g + c + 1).y();
      if (mu == 1.0)
        EXPECT_LE(std::abs(slip), 0.02 * std::abs(slip0[k]) + 1e-4);
      else
        EXPECT_NEAR(std::abs(slip), std::abs(slip0[k]) - 0.05 * 1.0, 0.005);
    }
  }
}

TEST(PhantomNodes, ThreeFragmentsMeetingResolveToTheTolerance) {
  // Three wedges of particles converging on the line x = y = 0.5.
  Fragments f;
  for (int s = 0; s < 3; ++s) {
    const double ang = 2.0 * M_PI * s / 3.0;
    const Vec3 dir(std::cos(ang), std::sin(ang), 0.0);
    for (int r = 1; r <= 6; ++r)
      for (int k = 0; k < 5; ++k) f.add(Vec3(0.5, 0.5, 0.4 + 0.04 * k) + 0.03 * r * dir, -dir, s, 1.0 + 0.1 * s);
  }
  Prepared pr;
  prepare(pr, f, [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return f.side[a] == f.side[b]; });
  bool three = false;
  for (size_t c = 0; c + 2 < pr.layout.copy_parent.size(); ++c)
    if (pr.layout.copy_parent[c] == pr.layout.copy_parent[c + 2]) three = true;
  EXPECT_TRUE(three);
  const Vec3 before = grid_momentum(pr.grid);
  const ContactStats st = resolve_phantom_contact(pr.grid, pr.layout.copy_kind, 1e-3, 0.3);
  EXPECT_LE(st.max_residual, 1e-4);
  EXPECT_LE((grid_momentum(pr.grid) - before).norm(), 1e-13 * (1.0 + before.norm()));
}

TEST(PhantomNodes, SolidNormalIsItsMassGradient) {
  // A solid slab below z = 0.5 and a shell sheet just above it, approaching: the contact removes only
  // the z velocity, because the solid's outward normal (Eq. 4.22, solid-shell case) is +z.
  Fragments f;
  std::vector<FieldKind> kinds;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      for (int k = 0; k < 4; ++k) f.add(Vec3(0.3 + 0.05 * i, 0.3 + 0.05 * j, 0.48 - 0.05 * k), Vec3(0.2, 0, 1), 0);
      f.add(Vec3(0.3 + 0.05 * i, 0.3 + 0.05 * j, 0.52), Vec3(0.2, 0, -1), 1);
    }
  Fragments solid, shell;
  for (size_t p = 0; p < f.x.size(); ++p) (f.side[p] == 0 ? solid : shell).add(f.x[p], f.v[p], f.side[p]);
  std::vector<ParticleSet> sets{solid.set(), shell.set()};
  SparseGrid grid(kDx);
  grid.rebuild(sets);
  const PhantomLayout layout = partition_nodes(
      grid, sets, {PartitionRole{FieldKind::Solid, solid.near.data()}, PartitionRole{FieldKind::Shell, shell.near.data()}},
      [](uint32_t sa, uint32_t, uint32_t sb, uint32_t) { return sa == sb; });
  grid.set_phantom_copies(layout);
  grid.transfer_mass_momentum(sets);
  grid.update_velocities(1e-3, Vec3::Zero());
  resolve_phantom_contact(grid, layout.copy_kind, 1e-3, 0.0);
  const size_t g = grid.num_grid_nodes();
  size_t checked = 0;
  for (size_t c = 0; c + 1 < layout.copy_parent.size(); ++c) {
    if (layout.copy_parent[c] != layout.copy_parent[c + 1]) continue;
    const Vec3 n = grid.copy_mass_gradient(c).normalized();
    EXPECT_EQ(layout.copy_kind[c], FieldKind::Solid);
    // Nodes over the slab's top face (z >= 0.5); deeper inside a solid the density gradient is no normal.
    const Vec3 xn = grid.node_position(g + c);
    if (std::abs(xn.x() - 0.475) > 0.12 || std::abs(xn.y() - 0.475) > 0.12 || xn.z() < 0.5 - 1e-9) continue;
    EXPECT_GT(n.z(), 0.9);
    EXPECT_LE(grid.node_velocity(g + c).z() - grid.node_velocity(g + c + 1).z(), 0.15);
    EXPECT_NEAR(grid.node_velocity(g + c).x(), 0.2, 1e-9);  // tangential motion untouched (mu = 0)
    ++checked;
  }
  EXPECT_GT(checked, 4u);
}

}  // namespace
}  // namespace shellfrac::mpm
