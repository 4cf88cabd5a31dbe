// The grid transfers use cached per-particle weights and factor the 27-node stencil sums by axis
// (mpm/sparse_grid.cpp). These tests evaluate the formulas node by node, as the transfers did before
// (thesis Eq. 2.15-2.17, 2.20-2.25 with the weights of Eq. 2.10-2.14), and compare.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

struct Cloud {
  std::vector<Vec3> x, v, f;
  std::vector<double> m;
  std::vector<Mat3> C, S, grad;
};

Cloud random_cloud(size_t n, unsigned seed, double extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), s(-1, 1);
  Cloud c;
  for (size_t i = 0; i < n; ++i) {
    // Off the origin, so that blocks with negative coordinates and block borders are crossed.
    c.x.push_back(Vec3(-0.31, 0.17, -0.05) + extent * Vec3(u(rng), u(rng), u(rng)));
    c.v.push_back(Vec3(s(rng), s(rng), s(rng)));
    c.f.push_back(Vec3(s(rng), s(rng), s(rng)));
    c.m.push_back(0.5 + u(rng));
    Mat3 a, b;
    for (int k = 0; k < 9; ++k) a(k / 3, k % 3) = 5 * s(rng);
    for (int k = 0; k < 9; ++k) b(k / 3, k % 3) = s(rng);
    c.C.push_back(a);
    c.S.push_back(b);
    c.grad.push_back(Mat3::Zero());
  }
  return c;
}

ParticleSet view(Cloud& c, bool affine, bool stress, bool mls, bool force) {
  ParticleSet s;
  s.count = c.x.size();
  s.position = c.x.data();
  s.velocity = c.v.data();
  s.mass = c.m.data();
  s.force = force ? c.f.data() : nullptr;
  s.stress = stress ? c.S.data() : nullptr;
  s.mls_force = mls;
  s.affine = affine ? c.C.data() : nullptr;
  s.velocity_gradient = c.grad.data();
  return s;
}

using Key = std::tuple<int, int, int>;

// Weight and weight gradient of stencil node `node` of a particle at x, as the node-by-node transfers
// formed them: the product of the axis weights (thesis Eq. 2.10, 2.11, 2.14; mpm/weights_test.cpp checks
// those against N(d)).
void weight(const Vec3& x, const Key& node, double dx, double& w, Vec3& grad) {
  const StencilWeights sw = stencil_weights(x, 1.0 / dx);
  const int i = std::get<0>(node) - sw.ax[0].base, j = std::get<1>(node) - sw.ax[1].base,
            k = std::get<2>(node) - sw.ax[2].base;
  w = sw.weight(i, j, k);
  grad = sw.gradient(i, j, k);
}

// The 27 stencil nodes of x.
std::vector<Key> stencil(const Vec3& x, double dx) {
  const StencilWeights sw = stencil_weights(x, 1.0 / dx);
  std::vector<Key> out;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) out.emplace_back(sw.ax[0].base + i, sw.ax[1].base + j, sw.ax[2].base + k);
  return out;
}

struct NodeSums {
  double m = 0, m_abs = 0;
  Vec3 p = Vec3::Zero(), p_abs = Vec3::Zero(), f = Vec3::Zero(), f_abs = Vec3::Zero();
};

// Reference p2g and force transfer: node by node, sums and sums of magnitudes (for the round-off bound).
std::map<Key, NodeSums> reference_scatter(const std::vector<ParticleSet>& sets, double dx) {
  std::map<Key, NodeSums> nodes;
  const double inv_d = apic_inverse_d(dx);
  for (const ParticleSet& s : sets)
    for (size_t p = 0; p < s.count; ++p) {
      const Vec3& xp = s.position[p];
      for (const Key& key : stencil(xp, dx)) {
        double w;
        Vec3 gw;
        weight(xp, key, dx, w, gw);
        const Vec3 xi = Vec3(std::get<0>(key), std::get<1>(key), std::get<2>(key)) * dx;
        NodeSums& n = nodes[key];
        n.m += w * s.mass[p];
        n.m_abs += std::abs(w * s.mass[p]);
        // Besides the sums, the magnitudes of the terms they are made of: the affine and MLS terms are
        // linear in x_i - x_p, and the factored transfer adds their parts d0 and dx (i, j, k) separately,
        // so its round-off is relative to |C| dx, not to |C (x_i - x_p)| (which may be small).
        const Vec3 reach = Vec3::Constant(4 * dx);  // bounds |d0| + dx (i + j + k) per component
        Vec3 mom = w * s.mass[p] * s.velocity[p];
        Vec3 mom_abs = mom.cwiseAbs();
        if (s.affine) {
          mom += w * s.mass[p] * s.affine[p] * (xi - xp);  // Eq. 2.23
          mom_abs += std::abs(w * s.mass[p]) * (s.affine[p].cwiseAbs() * reach);
        }
        n.p += mom;
        n.p_abs += mom_abs;
        Vec3 f = Vec3::Zero(), f_abs = Vec3::Zero();
        if (s.force) {
          f += w * s.force[p];
          f_abs += (w * s.force[p]).cwiseAbs();
        }
        if (s.stress && s.mls_force) {
          f -= inv_d * w * s.stress[p] * (xi - xp);  // Eq. 2.24
          f_abs += std::abs(inv_d * w) * (s.stress[p].cwiseAbs() * reach);
        } else if (s.stress) {
          f -= s.stress[p] * gw;  // Eq. 2.17
          f_abs += s.stress[p].cwiseAbs() * gw.cwiseAbs();
        }
        n.f += f;
        n.f_abs += f_abs;
      }
    }
  return nodes;
}

void expect_scatter_matches(const SparseGrid& g, const std::vector<ParticleSet>& sets, double dx) {
  const std::map<Key, NodeSums> ref = reference_scatter(sets, dx);
  double m_grid = 0, m_ref = 0;
  Vec3 p_grid = Vec3::Zero(), p_ref = Vec3::Zero();
  for (const auto& [key, r] : ref) {
    const long n = g.node_index(std::get<0>(key), std::get<1>(key), std::get<2>(key));
    ASSERT_GE(n, 0);
    const size_t i = static_cast<size_t>(n);
    // Summing the same few contributions in another order: within a few ulps of the magnitude sum.
    EXPECT_LE(std::abs(g.node_mass(i) - r.m), 1e-14 * r.m_abs);
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(std::abs(g.node_momentum(i)[c] - r.p[c]), 1e-14 * r.p_abs[c] + 1e-300);
      EXPECT_LE(std::abs(g.node_force(i)[c] - r.f[c]), 1e-14 * r.f_abs[c] + 1e-300);
    }
    m_ref += r.m;
    p_ref += r.p;
  }
  // Nothing anywhere else.
  for (size_t n = 0; n < g.num_nodes(); ++n) {
    m_grid += g.node_mass(n);
    p_grid += g.node_momentum(n);
  }
  EXPECT_NEAR(m_grid, m_ref, 1e-13 * m_ref);
  EXPECT_LE((p_grid - p_ref).norm(), 1e-13 * (1.0 + p_ref.norm()));
}

TEST(TransferReference, ScatterEqualsTheNodeByNodeFormulas) {
  const double dx = 0.05;
  for (int variant = 0; variant < 4; ++variant) {
    const bool affine = variant & 1, mls = variant & 2;
    Cloud a = random_cloud(300, 11 + static_cast<unsigned>(variant), 0.4);
    Cloud b = random_cloud(200, 31 + static_cast<unsigned>(variant), 0.4);
    // A set with force and stress (and APIC), and a set with the force alone.
    std::vector<ParticleSet> sets{view(a, affine, true, mls, true), view(b, false, false, false, true)};
    SparseGrid g(dx);
    g.rebuild(sets);
    g.transfer_mass_momentum(sets);
    g.transfer_forces(sets);
    SCOPED_TRACE(variant);
    expect_scatter_matches(g, sets, dx);
  }
}

TEST(TransferReference, P2gConservesMassAndMomentumToRoundOff) {
  const double dx = 0.03;
  Cloud a = random_cloud(2000, 5, 0.5);
  for (bool affine : {false, true}) {
    std::vector<ParticleSet> sets{view(a, affine, false, false, false)};
    SparseGrid g(dx);
    g.rebuild(sets);
    g.transfer_mass_momentum(sets);
    double m_grid = 0, m_part = 0, m_abs = 0;
    Vec3 p_grid = Vec3::Zero(), p_part = Vec3::Zero(), p_abs = Vec3::Zero();
    for (size_t n = 0; n < g.num_nodes(); ++n) {
      m_grid += g.node_mass(n);
      p_grid += g.node_momentum(n);
      p_abs += g.node_momentum(n).cwiseAbs();
    }
    for (size_t p = 0; p < a.x.size(); ++p) {
      m_part += a.m[p];
      m_abs += a.m[p];
      p_part += a.m[p] * a.v[p];  // the weights sum to one, and sum_i w (x_i - x_p) = 0 (APIC, Eq. 2.23)
    }
    // Round-off of sums of a few hundred thousand terms of either sign.
    EXPECT_NEAR(m_grid, m_part, 1e-13 * m_abs);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p_grid[c], p_part[c], 1e-13 * (p_abs[c] + m_abs));
  }
}

TEST(TransferReference, GatherEqualsTheNodeByNodeFormulas) {
  const double dx = 0.05;
  for (bool affine : {false, true})
    for (double flip : {0.0, 0.7}) {
      Cloud a = random_cloud(400, 7, 0.4);
      std::vector<ParticleSet> sets{view(a, affine, true, false, true)};
      sets[0].flip = flip;
      SparseGrid g(dx);
      g.rebuild(sets);
      g.transfer_mass_momentum(sets);
      g.transfer_forces(sets);
      g.update_velocities(1e-3, Vec3(0, -9.81, 0));
      // A non-trivial field on the nodes (forces and gravity changed it).
      const std::vector<Vec3> v_before = a.v;
      g.transfer_to_particles(sets);
      const double inv_d = apic_inverse_d(dx);
      double vmax = 0;
      for (size_t n = 0; n < g.num_nodes(); ++n) vmax = std::max(vmax, g.node_velocity(n).norm());
      for (size_t p = 0; p < a.x.size(); ++p) {
        const Vec3& xp = a.x[p];
        Vec3 v = Vec3::Zero(), v_old = Vec3::Zero(), v_old_abs = Vec3::Zero();
        Mat3 C = Mat3::Zero(), G = Mat3::Zero();
        for (const Key& key : stencil(xp, dx)) {
          double w;
          Vec3 gw;
          weight(xp, key, dx, w, gw);
          const size_t n = static_cast<size_t>(g.node_index(std::get<0>(key), std::get<1>(key), std::get<2>(key)));
          const Vec3 xi = Vec3(std::get<0>(key), std::get<1>(key), std::get<2>(key)) * dx;
          const Vec3& vi = g.node_velocity(n);
          v += w * vi;                                         // Eq. 2.20
          C += inv_d * w * vi * (xi - xp).transpose();         // Eq. 2.25
          G += vi * gw.transpose();
          if (g.node_mass(n) > 0) {
            v_old += (w / g.node_mass(n)) * g.node_momentum(n);
            v_old_abs += ((w / g.node_mass(n)) * g.node_momentum(n)).cwiseAbs();
          }
        }
        const Vec3 expected = flip > 0 ? Vec3(v + flip * (v_before[p] - v_old)) : v;
        // Scales: velocities up to vmax; C and the gradient up to about vmax / dx.
        const double tol_v = 1e-14 * (vmax + (flip > 0 ? v_old_abs.maxCoeff() + v_before[p].norm() : 0.0));
        EXPECT_LE((a.v[p] - expected).cwiseAbs().maxCoeff(), tol_v) << p;
        if (affine) {
          EXPECT_LE((a.C[p] - C).cwiseAbs().maxCoeff(), 1e-14 * vmax * inv_d * dx) << p;
        }
        EXPECT_LE((a.grad[p] - G).cwiseAbs().maxCoeff(), 1e-14 * vmax / dx) << p;
      }
    }
}

TEST(TransferReference, CachedStencilEqualsTheStencilOfThePosition) {
  Cloud a = random_cloud(500, 3, 0.6), b = random_cloud(100, 4, 0.6);
  std::vector<ParticleSet> sets{view(a, false, false, false, false), view(b, false, false, false, false)};
  SparseGrid g(0.04);
  g.rebuild(sets);
  for (size_t s = 0; s < sets.size(); ++s)
    for (size_t p = 0; p < sets[s].count; ++p) {
      const std::array<uint32_t, 27> fresh = g.stencil_nodes(sets[s].position[p]);
      const uint32_t* cached = g.particle_stencil(s, p);
      const std::vector<Key> keys = stencil(sets[s].position[p], 0.04);
      for (size_t k = 0; k < 27; ++k) {
        EXPECT_EQ(cached[k], fresh[k]);
        EXPECT_EQ(static_cast<long>(cached[k]), g.node_index(std::get<0>(keys[k]), std::get<1>(keys[k]), std::get<2>(keys[k])));
      }
    }
}

}  // namespace
}  // namespace shellfrac::mpm
