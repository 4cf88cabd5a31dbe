// The transfer kernels of SolidGrid (generic and, where the processor has it, AVX2 with FMA) against the
// plain formulas of p2g and g2p (thesis Eq. 2.20, 2.23-2.26, 3.3-3.5) on random particles with two velocity
// fields, their conservation of mass and momentum, and their independence of the thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "brittle/crack_sides.hpp"
#include "brittle/errors.hpp"
#include "brittle/solid_grid.hpp"
#include "brittle_test_helpers.hpp"

namespace shellfrac::brittle {
namespace {

constexpr double kDx = 0.01, kDt = 1e-4;

// Random particles in a 6 x 4 x 5 cm box with random velocities, affine matrices, stresses and, for
// half of them, crack data: a slot with a unit normal and a random 27-bit field mask (a quarter of
// those all field 0).
struct RandomParticles {
  std::vector<GVec3> x, v, n;
  std::vector<double> m;
  std::vector<GMat3> C, F, stress;
  std::vector<FieldMask> mask;
  std::vector<int32_t> slot;

  explicit RandomParticles(size_t count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto random_matrix = [&] {  // entries uniform in [-1, 1], from this seed
      GMat3 a;
      for (int c = 0; c < 9; ++c) a(c) = u(rng);
      return a;
    };
    for (size_t p = 0; p < count; ++p) {
      x.emplace_back(0.03 * u(rng) + 0.011, 0.02 * u(rng) - 0.004, 0.025 * u(rng) + 0.1);
      v.push_back(GVec3(u(rng), u(rng), u(rng)));
      m.push_back(0.5 + 0.25 * u(rng));
      C.push_back(50.0 * random_matrix());
      F.push_back(GMat3::Identity() + 0.05 * random_matrix());
      const GMat3 a = random_matrix();
      stress.push_back(1e-2 * (a + a.transpose()));
      if (rng() % 2) {
        slot.push_back(static_cast<int32_t>(n.size()));
        n.push_back(GVec3(u(rng), u(rng), u(rng)).normalized());
        mask.push_back(rng() % 4 == 0 ? 0u : static_cast<FieldMask>(rng() & ((1u << 27) - 1)));
      } else {
        slot.push_back(-1);
        mask.push_back(0);
      }
    }
  }
  SolidView view() {
    SolidView s;
    s.count = x.size();
    s.x = x.data();
    s.v = v.data();
    s.m = m.data();
    s.C = C.data();
    s.F = F.data();
    s.stress = stress.data();
    s.mask = mask.data();
    s.near_slot = slot.data();
    s.near_normal = n.data();
    return s;
  }
};

// Quadratic B-spline weight of a node at integer coordinate i for a particle at q = x / h (Eq. 2.10).
double bspline(double r) {
  r = std::abs(r);
  if (r < 0.5) return 0.75 - r * r;
  if (r < 1.5) return 0.5 * (1.5 - r) * (1.5 - r);
  return 0.0;
}

// Calls fn(i, j, k, w) for the 27 nodes around x (integer coordinates), the straightforward way.
template <class Fn>
void for_stencil(const GVec3& x, Fn&& fn) {
  int base[3];
  for (int a = 0; a < 3; ++a) base[a] = static_cast<int>(std::floor(x[a] * (1.0 / kDx) - 0.5));
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const int node[3] = {base[0] + i, base[1] + j, base[2] + k};
        double w = 1.0;
        for (int a = 0; a < 3; ++a) w *= bspline(x[a] * (1.0 / kDx) - node[a]);
        fn(node[0], node[1], node[2], i + 3 * j + 9 * k, w);
      }
}

struct ReferenceGrid {
  std::vector<double> m[2];
  std::vector<GVec3> p[2], normal;
};

// p2g by the formulas: m_i = sum w m_p, (m v)_i = sum w (m_p v_p + (m_p C_p - dt D^-1 stress_p)(x_i - x_p))
// per field, crack normal sum +-w m_p n_p.
ReferenceGrid reference_p2g(const SolidGrid& g, const RandomParticles& r) {
  ReferenceGrid out;
  const size_t nodes = g.num_nodes();
  for (int f = 0; f < 2; ++f) {
    out.m[f].assign(nodes, 0.0);
    out.p[f].assign(nodes, GVec3::Zero());
  }
  out.normal.assign(nodes, GVec3::Zero());
  const double inv_d = 4.0 / (kDx * kDx);
  for (size_t q = 0; q < r.x.size(); ++q) {
    const GMat3 Q = r.m[q] * r.C[q] - kDt * inv_d * r.stress[q];
    for_stencil(r.x[q], [&](int i, int j, int k, int bit, double w) {
      const long idx = g.node_index(i, j, k);
      ASSERT_GE(idx, 0);
      const int f = static_cast<int>((r.mask[q] >> bit) & 1u);
      const GVec3 d = GVec3(i, j, k) * kDx - r.x[q];
      out.m[f][idx] += w * r.m[q];
      out.p[f][idx] += w * (r.m[q] * r.v[q] + Q * d);
      if (r.slot[q] >= 0) out.normal[idx] += (f ? -1.0 : 1.0) * w * r.m[q] * r.n[r.slot[q]];
    });
  }
  return out;
}

std::vector<SolidGrid::TransferIsa> isas() {
  std::vector<SolidGrid::TransferIsa> out{SolidGrid::TransferIsa::Generic};
  SolidGrid probe(kDx);
  if (probe.set_transfer_isa(SolidGrid::TransferIsa::Avx2)) out.push_back(SolidGrid::TransferIsa::Avx2);
  return out;
}

double max_abs(const std::vector<GVec3>& a) {
  double s = 0;
  for (const GVec3& v : a) s = std::max(s, v.cwiseAbs().maxCoeff());
  return s;
}

TEST(SolidTransfer, ScatterEqualsTheFormulasAndConservesMassAndMomentumWithTwoFields) {
  RandomParticles r(3000, 7);
  for (SolidGrid::TransferIsa isa : isas()) {
    SolidGrid g(kDx);
    ASSERT_TRUE(g.set_transfer_isa(isa));
    SCOPED_TRACE(g.transfer_isa());
    g.rebuild(r.x.data(), r.x.size(), {}, true, size_t{1} << 30);
    g.transfer_to_grid(r.view(), kDt);
    const ReferenceGrid ref = reference_p2g(g, r);
    // Relative to the largest value of each quantity over the grid.
    const double scale_m = *std::max_element(ref.m[0].begin(), ref.m[0].end());
    const double scale_p = std::max(max_abs(ref.p[0]), max_abs(ref.p[1]));
    const double scale_n = max_abs(ref.normal);
    double err_m = 0, err_p = 0, err_n = 0;
    for (size_t i = 0; i < g.num_nodes(); ++i) {
      for (int f = 0; f < 2; ++f) {
        const GridNode& nd = g.node(f, i);
        err_m = std::max(err_m, std::abs(nd.m - ref.m[f][i]));
        err_p = std::max(err_p, (GVec3(nd.p[0], nd.p[1], nd.p[2]) - ref.p[f][i]).cwiseAbs().maxCoeff());
      }
      err_n = std::max(err_n, (g.crack_normal(i) - ref.normal[i]).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(err_m, 1e-12 * scale_m);
    EXPECT_LE(err_p, 1e-12 * scale_p);
    EXPECT_LE(err_n, 1e-12 * scale_n);

    // Conservation: sum_i w_ip = 1 and sum_i w_ip (x_i - x_p) = 0 for quadratic B-splines, so the grid
    // holds exactly the particles' mass and momentum (the stress and affine terms cancel); round-off
    // relative to sum m_p and sum m_p |v_p| + |Q_p| h.
    double mass = 0, grid_mass = 0, scale = 0;
    GVec3 mom = GVec3::Zero(), grid_mom = GVec3::Zero();
    for (size_t q = 0; q < r.x.size(); ++q) {
      mass += r.m[q];
      mom += r.m[q] * r.v[q];
      scale += r.m[q] * r.v[q].norm() + (r.m[q] * r.C[q] - kDt * 4.0 / (kDx * kDx) * r.stress[q]).norm() * kDx;
    }
    for (size_t i = 0; i < g.num_nodes(); ++i)
      for (int f = 0; f < 2; ++f) {
        grid_mass += g.node(f, i).m;
        grid_mom += GVec3(g.node(f, i).p[0], g.node(f, i).p[1], g.node(f, i).p[2]);
      }
    EXPECT_NEAR(grid_mass, mass, 1e-13 * mass);
    EXPECT_LE((grid_mom - mom).cwiseAbs().maxCoeff(), 1e-14 * scale);
  }
}

TEST(SolidTransfer, GatherEqualsTheFormulas) {
  const RandomParticles start(3000, 11);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double inv_d = 4.0 / (kDx * kDx);
  for (SolidGrid::TransferIsa isa : isas()) {
    RandomParticles r = start;
    SolidGrid g(kDx);
    ASSERT_TRUE(g.set_transfer_isa(isa));
    SCOPED_TRACE(g.transfer_isa());
    g.rebuild(r.x.data(), r.x.size(), {}, true, size_t{1} << 30);
    // Random node velocities in both fields (the momentum slots hold velocities after the grid update).
    for (size_t i = 0; i < g.num_nodes(); ++i)
      for (int f = 0; f < 2; ++f) {
        GridNode& nd = g.node(f, i);
        nd.m = 1.0 + u(rng);
        for (int a = 0; a < 3; ++a) nd.p[a] = u(rng);
      }
    g.transfer_to_particles(r.view(), kDt);
    double err_v = 0, err_c = 0, err_f = 0, err_x = 0, scale_c = 0;
    for (size_t q = 0; q < r.x.size(); ++q) {
      GVec3 v = GVec3::Zero();
      GMat3 B = GMat3::Zero();
      for_stencil(start.x[q], [&](int i, int j, int k, int bit, double w) {
        const GridNode& nd = g.node(static_cast<int>((start.mask[q] >> bit) & 1u), static_cast<size_t>(g.node_index(i, j, k)));
        const GVec3 vi(nd.p[0], nd.p[1], nd.p[2]);
        v += w * vi;
        B += w * vi * (GVec3(i, j, k) * kDx - start.x[q]).transpose();
      });
      const GMat3 C = inv_d * B;
      const GMat3 F = (GMat3::Identity() + kDt * C) * start.F[q];
      const GVec3 x = start.x[q] + kDt * v;
      scale_c = std::max(scale_c, C.cwiseAbs().maxCoeff());
      err_v = std::max(err_v, (r.v[q] - v).cwiseAbs().maxCoeff());
      err_c = std::max(err_c, (r.C[q] - C).cwiseAbs().maxCoeff());
      err_f = std::max(err_f, (r.F[q] - F).cwiseAbs().maxCoeff() / F.cwiseAbs().maxCoeff());
      err_x = std::max(err_x, (r.x[q] - x).cwiseAbs().maxCoeff() / x.cwiseAbs().maxCoeff());
    }
    EXPECT_LE(err_v, 1e-12);  // node speeds are at most 1
    EXPECT_LE(err_c, 1e-12 * scale_c);
    EXPECT_LE(err_f, 1e-12);
    EXPECT_LE(err_x, 1e-12);
  }
}

TEST(SolidTransfer, KernelsAreBitIdenticalForOneAndTwoThreads) {
  for (SolidGrid::TransferIsa isa : isas()) {
    std::vector<GridNode> nodes[2];
    std::vector<GVec3> normals[2];
    RandomParticles after[2] = {RandomParticles(20000, 5), RandomParticles(20000, 5)};
    for (int t = 0; t < 2; ++t) {
      tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(t + 1));
      RandomParticles& r = after[t];
      SolidGrid g(kDx);
      ASSERT_TRUE(g.set_transfer_isa(isa));
      g.rebuild(r.x.data(), r.x.size(), {}, true, size_t{1} << 30);
      g.transfer_to_grid(r.view(), kDt);
      for (size_t i = 0; i < g.num_nodes(); ++i) {
        for (int f = 0; f < 2; ++f) nodes[t].push_back(g.node(f, i));
        normals[t].push_back(g.crack_normal(i));
      }
      g.update_velocities(kDt, GVec3(0, 0, -9.81));
      g.resolve_field_contact();
      g.transfer_to_particles(r.view(), kDt);
    }
    ASSERT_EQ(nodes[0].size(), nodes[1].size());
    for (size_t i = 0; i < nodes[0].size(); ++i) {
      ASSERT_EQ(nodes[0][i].m, nodes[1][i].m);
      for (int a = 0; a < 3; ++a) ASSERT_EQ(nodes[0][i].p[a], nodes[1][i].p[a]);
    }
    EXPECT_TRUE(normals[0] == normals[1]);
    EXPECT_TRUE(after[0].x == after[1].x);
    EXPECT_TRUE(after[0].v == after[1].v);
    EXPECT_TRUE(after[0].C == after[1].C);
    EXPECT_TRUE(after[0].F == after[1].F);
  }
}

TEST(SolidTransfer, GenericAndAvx2KernelsAgreeToRoundOff) {
  SolidGrid probe(kDx);
  if (!probe.set_transfer_isa(SolidGrid::TransferIsa::Avx2)) GTEST_SKIP() << "no AVX2 with FMA on this processor";
  RandomParticles r[2] = {RandomParticles(5000, 9), RandomParticles(5000, 9)};
  std::vector<GridNode> nodes[2];
  const SolidGrid::TransferIsa isa[2] = {SolidGrid::TransferIsa::Generic, SolidGrid::TransferIsa::Avx2};
  for (int t = 0; t < 2; ++t) {
    SolidGrid g(kDx);
    ASSERT_TRUE(g.set_transfer_isa(isa[t]));
    g.rebuild(r[t].x.data(), r[t].x.size(), {}, true, size_t{1} << 30);
    g.transfer_to_grid(r[t].view(), kDt);
    for (size_t i = 0; i < g.num_nodes(); ++i)
      for (int f = 0; f < 2; ++f) nodes[t].push_back(g.node(f, i));
    g.update_velocities(kDt, GVec3::Zero());
    g.transfer_to_particles(r[t].view(), kDt);
  }
  double scale = 0, err = 0;
  for (size_t i = 0; i < nodes[0].size(); ++i)
    for (int a = 0; a < 3; ++a) {
      scale = std::max(scale, std::abs(nodes[0][i].p[a]));
      err = std::max(err, std::abs(nodes[0][i].p[a] - nodes[1][i].p[a]));
    }
  EXPECT_LE(err, 1e-12 * scale);
  double err_v = 0, scale_v = 0;
  for (size_t q = 0; q < r[0].x.size(); ++q) {
    scale_v = std::max(scale_v, r[0].v[q].cwiseAbs().maxCoeff());
    err_v = std::max(err_v, (r[0].v[q] - r[1].v[q]).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(err_v, 1e-12 * scale_v);
}

// The two-field classification (thesis sec. 3.4.1, CrackSides::classify) against a direct computation:
// particle p is in field 1 at node i when n_p . n_ref < -1/4, n_ref the normal of the near particle with
// the largest weight at i. Nodes where several particles share the largest weight to 1e-12 and disagree
// are left out (the classifier breaks such ties by scatter order).
TEST(CrackSides, FieldMasksFollowTheReferenceParticleOfEachNode) {
  // A 12 x 12 x 12 lattice (spacing h / 2) cracked by the plane z = 0 and deformed a little at random.
  std::vector<Vec3> rest, x;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double s = 0.5 * kDx;
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i) {
        rest.emplace_back(s * (i - 5.5), s * (j - 5.5), s * (k - 5.5));
        x.push_back(rest.back() + 0.2 * s * Vec3(u(rng), u(rng), u(rng)) + Vec3(0.003, -0.002, 0.05));
      }
  CrackSides sides;
  sides.set_crack(testing::square_z(0, 0, 0, 1.0), rest, 3.0 * std::sqrt(3.0) * kDx * 1.05, kDx);
  ASSERT_TRUE(sides.active());
  SolidGrid g(kDx);
  g.rebuild(x.data(), x.size(), {}, true, size_t{1} << 30);
  sides.classify(g, x.data());

  const size_t nodes = g.num_nodes();
  std::vector<double> best(nodes, -1.0);
  auto near = [&](size_t p) { return sides.slot(p) >= 0; };
  for (size_t p = 0; p < x.size(); ++p)
    if (near(p))
      for_stencil(x[p], [&](int i, int j, int k, int, double w) {
        const size_t idx = static_cast<size_t>(g.node_index(i, j, k));
        best[idx] = std::max(best[idx], w);
      });
  std::vector<std::vector<size_t>> leaders(nodes);
  for (size_t p = 0; p < x.size(); ++p)
    if (near(p))
      for_stencil(x[p], [&](int i, int j, int k, int, double w) {
        const size_t idx = static_cast<size_t>(g.node_index(i, j, k));
        if (w >= best[idx] * (1.0 - 1e-12)) leaders[idx].push_back(p);
      });
  size_t checked = 0, skipped = 0, field1 = 0;
  for (size_t p = 0; p < x.size(); ++p) {
    const FieldMask mask = sides.masks()[p];
    if (!near(p)) {
      EXPECT_EQ(mask, 0u) << "far particle " << p;
      continue;
    }
    const Vec3 np = sides.normals()[sides.slot(p)];
    for_stencil(x[p], [&](int i, int j, int k, int bit, double) {
      const size_t idx = static_cast<size_t>(g.node_index(i, j, k));
      int votes[2] = {0, 0};
      bool close = false;
      for (size_t q : leaders[idx]) {
        const double d = np.dot(sides.normals()[sides.slot(q)]);
        close = close || std::abs(d - CrackSides::kOppositeCosine) < 1e-12;
        ++votes[d < CrackSides::kOppositeCosine ? 1 : 0];
      }
      if (close || (votes[0] && votes[1])) {
        ++skipped;
        return;
      }
      const unsigned expected = votes[1] ? 1u : 0u;
      EXPECT_EQ((mask >> bit) & 1u, expected) << "particle " << p << " node " << idx;
      ++checked;
      field1 += expected;
    });
  }
  EXPECT_GT(field1, 1000u);  // both sides really occur
  EXPECT_LT(skipped, checked / 10);
}

// Material flown far apart (the diverging events of a strong impact: particles 1e12 m from the rest,
// finite but beyond any int node index) is refused before anything is allocated, with the grid it would
// need, not by a failed allocation. The same for an extent within int range but above the memory limit.
TEST(SolidGridRebuild, MaterialFlownFarApartIsRefusedBeforeAllocating) {
  SolidGrid g(0.01);
  for (double far : {1e12, 50.0}) {
    const std::vector<GVec3> x = {GVec3(0, 0, 0), GVec3(0.01, 0.0, 0.0), GVec3(far, -far, far)};
    try {
      g.rebuild(x.data(), x.size(), {}, true, size_t{1} << 30);
      ADD_FAILURE() << "a grid spanning " << far << " m was built";
    } catch (const NumericalError& e) {
      EXPECT_NE(std::string(e.what()).find("material has flown far apart"), std::string::npos) << e.what();
    }
  }
  // A grid that fits is still built after a refusal.
  const std::vector<GVec3> near = {GVec3(0, 0, 0), GVec3(0.05, 0.02, 0.01)};
  g.rebuild(near.data(), near.size(), {}, false, size_t{1} << 30);
  EXPECT_EQ(g.dims(), Eigen::Vector3i(8, 5, 4));
}

}  // namespace
}  // namespace shellfrac::brittle
