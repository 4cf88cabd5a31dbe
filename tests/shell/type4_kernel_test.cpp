// The batched Type IV force kernel against the scalar reference, point by point, and the lane versions of
// ln and e^x against libm.
#include "shell/type4_kernel.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "nurbs/patch_builders.hpp"
#include "shell/quadrature.hpp"
#include "shell/shell_patch.hpp"
#include "tests/shell/shell_test_helpers.hpp"

namespace shellfrac::shell {
// The lane helpers are file-local by design; the test includes its own copy. 8-double vectors never cross a
// call boundary here either (the psabi note is about that).
#pragma GCC diagnostic ignored "-Wpsabi"
namespace lanes_under_test {
namespace {
#include "shell/simd_lanes.hpp"
}  // namespace
}  // namespace lanes_under_test

namespace {

using test::max_norm;

// ulp distance between two finite doubles of the same sign.
double ulps(double a, double b) { return std::abs(a - b) / (std::nextafter(std::abs(b), INFINITY) - std::abs(b)); }

TEST(Type4Lanes, LogAndExpAreWithinTwoUlpOfLibm) {
  using namespace lanes_under_test;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> exponent(-300, 300), near_one(-1e-3, 1e-3), arg(-700, 700);
  double worst_log = 0, worst_exp = 0;
  for (int rep = 0; rep < 4000; ++rep) {
    Lanes x, y;
    for (int i = 0; i < kLanes; ++i) {
      // wide range, and the neighbourhood of 1 where ln x is small and cancellation would show
      x.set(i, rep % 2 ? std::pow(10.0, exponent(rng)) : 1.0 + near_one(rng));
      y.set(i, rep % 3 ? arg(rng) : 1e-3 * arg(rng));
    }
    const Lanes l = vlog(x), e = vexp(y);
    for (int i = 0; i < kLanes; ++i) {
      if (x[i] != 1.0) worst_log = std::max(worst_log, ulps(l[i], std::log(x[i])));
      worst_exp = std::max(worst_exp, ulps(e[i], std::exp(y[i])));
    }
  }
  // The Taylor and atanh series are truncated below 1e-17 relative; what remains is rounding in Horner's
  // scheme and the final scaling (about 1 ulp each).
  EXPECT_LE(worst_log, 2.0);
  EXPECT_LE(worst_exp, 2.0);
}

// Eight quadrature points of a patch, with their own copies of the material state, evaluated by either
// kernel.
struct PointSet {
  nurbs::NurbsSurface surface;
  int n = 0, layers = 3;
  std::vector<double> xi3{-0.005, 0.0, 0.005};
  std::vector<Vec3> x;
  std::vector<std::vector<int>> support;      // per point
  std::vector<std::vector<double>> basis;     // per point, stride 6
  std::vector<double> lanes;                  // n x 5 x 8
  std::vector<ReferenceLayer> ref;
  std::vector<double> volume, alpha, damage, history, sigma_f, H;

  PointSet(const nurbs::NurbsSurface& s, unsigned seed) : surface(s) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u01(0.02, 0.98);
    x.assign(s.control_points().begin(), s.control_points().end());
    nurbs::SurfaceBasis sb;
    for (int i = 0; i < kType4Lanes; ++i) {
      s.rational_basis(u01(rng), u01(rng), sb);
      n = sb.count;
      support.emplace_back(sb.index.begin(), sb.index.begin() + n);
      std::vector<double> b(static_cast<size_t>(6 * n));
      for (int k = 0; k < n; ++k) {
        const double v[6] = {sb.R[k], sb.Ru[k], sb.Rv[k], sb.Ruu[k], sb.Ruv[k], sb.Rvv[k]};
        for (int j = 0; j < 6; ++j) b[static_cast<size_t>(6 * k + j)] = v[j];
      }
      basis.push_back(b);
      // reference metric of each layer from the undeformed patch
      const Vec3* pts[kType4MaxSupport];
      for (int k = 0; k < n; ++k) pts[k] = &x[static_cast<size_t>(support.back()[static_cast<size_t>(k)])];
      const SurfaceJet jet = surface_jet(pts, b.data() + 1, n, 6);
      NormalJet nj;
      EXPECT_TRUE(normal_jet(jet, nj));
      for (int l = 0; l < layers; ++l) {
        ref.push_back(reference_layer(kl_basis(jet, nj, xi3[static_cast<size_t>(l)])));
        volume.push_back(1e-3 * ref.back().sqrt_det);
      }
    }
    lanes.assign(static_cast<size_t>(n * 5 * kType4Lanes), 0.0);
    for (int i = 0; i < kType4Lanes; ++i)
      for (int s2 = 0; s2 < n; ++s2)
        for (int k = 0; k < 5; ++k)
          lanes[static_cast<size_t>((s2 * 5 + k) * kType4Lanes + i)] = basis[static_cast<size_t>(i)][static_cast<size_t>(6 * s2 + 1 + k)];
    const size_t m = ref.size();
    alpha.assign(m, 0.0);
    damage.assign(m, 0.0);
    history.assign(m, 0.0);
    sigma_f.assign(kType4Lanes, 1e300);
    H.assign(kType4Lanes, 1.0);
  }

  Type4Data data(Type4Data d) {
    d.layers = layers;
    d.xi3 = xi3.data();
    d.x = x.data();
    d.ref = ref.data();
    d.volume = volume.data();
    d.plastic_strain = alpha.data();
    d.damage = damage.data();
    d.damage_history = history.data();
    d.failure_stress = sigma_f.data();
    d.brittleness = H.data();
    return d;
  }
};

struct Outcome {
  std::vector<std::vector<Vec3>> force;  // per lane, per support
  std::vector<int> status;
  std::vector<ReferenceLayer> ref;
  std::vector<double> alpha, damage, history;
};

Outcome run_scalar(PointSet p, const Type4Data& base, unsigned active = 0xffu) {
  const Type4Data d = p.data(base);
  Outcome o;
  for (int i = 0; i < kType4Lanes; ++i) {
    std::vector<Vec3> f(static_cast<size_t>(p.n), Vec3::Zero());
    int st = kType4Ok;
    if ((active >> i) & 1u)
      st = type4_point_force(d, static_cast<size_t>(i), {p.n, p.support[static_cast<size_t>(i)].data(), p.basis[static_cast<size_t>(i)].data()},
                             false, 0.97, f.data());
    o.force.push_back(f);
    o.status.push_back(st);
  }
  o.ref = p.ref;
  o.alpha = p.alpha;
  o.damage = p.damage;
  o.history = p.history;
  return o;
}

using BatchKernel = void (*)(const Type4Data&, const Type4Batch&, Type4BatchResult&);

Outcome run_batched(PointSet p, const Type4Data& base, unsigned active = 0xffu, BatchKernel kernel = type4_force_batch) {
  const Type4Data d = p.data(base);
  Type4Batch b;
  b.n = p.n;
  b.active = active;
  b.basis = p.lanes.data();
  for (int i = 0; i < kType4Lanes; ++i) {
    b.q[i] = static_cast<size_t>(i);
    b.support[i] = p.support[static_cast<size_t>(i)].data();
    b.r33[i] = 0.97;
  }
  auto r = std::make_unique<Type4BatchResult>();
  kernel(d, b, *r);
  Outcome o;
  for (int i = 0; i < kType4Lanes; ++i) {
    std::vector<Vec3> f(static_cast<size_t>(p.n), Vec3::Zero());
    if ((active >> i) & 1u)
      for (int s = 0; s < p.n; ++s) f[static_cast<size_t>(s)] = Vec3(r->force[s][0][i], r->force[s][1][i], r->force[s][2][i]);
    o.force.push_back(f);
    o.status.push_back((active >> i) & 1u ? r->status[i] : kType4Ok);
  }
  o.ref = p.ref;
  o.alpha = p.alpha;
  o.damage = p.damage;
  o.history = p.history;
  return o;
}

// Largest relative difference per point: force differences against that point's largest force, state
// differences against the state's own size.
double mismatch(const Outcome& a, const Outcome& b) {
  double worst = 0;
  for (size_t i = 0; i < a.force.size(); ++i) {
    EXPECT_EQ(a.status[i], b.status[i]) << "lane " << i;
    const double scale = max_norm(b.force[i]);
    for (size_t s = 0; s < a.force[i].size(); ++s)
      worst = std::max(worst, (a.force[i][s] - b.force[i][s]).norm() / std::max(scale, 1e-300));
  }
  auto rel = [&](double u, double v) { return std::abs(u - v) / std::max(std::abs(v), 1e-300); };
  for (size_t k = 0; k < a.ref.size(); ++k) {
    worst = std::max({worst, rel(a.ref[k].g11, b.ref[k].g11), rel(a.ref[k].g22, b.ref[k].g22),
                      rel(a.ref[k].sqrt_det, b.ref[k].sqrt_det)});
    // g12 of a nearly orthogonal metric is a small difference: compare it on the metric's scale
    worst = std::max(worst, std::abs(a.ref[k].g12 - b.ref[k].g12) / std::abs(b.ref[k].g11));
    worst = std::max(worst, a.alpha[k] > 0 || b.alpha[k] > 0 ? rel(a.alpha[k], b.alpha[k]) : 0.0);
    worst = std::max(worst, std::abs(a.damage[k] - b.damage[k]));  // c in [0, 1]
    worst = std::max(worst, std::abs(a.history[k] - b.history[k]));
  }
  return worst;
}

// Deformations of a flat 1 m x 1 m patch (4 x 4 cells), each plus 0.2% random noise on the control points.
using Deformation = std::function<Vec3(const Vec3&)>;
void deform(PointSet& p, const Deformation& f, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.002, 0.002);
  for (Vec3& x : p.x) x = f(x) + Vec3(u(rng), u(rng), u(rng));
}
const Deformation kStretched = [](const Vec3& X) { return Vec3(1.15 * X.x(), 0.97 * X.y() + 0.05 * X.x(), X.z()); };
const Deformation kCompressed = [](const Vec3& X) { return Vec3(0.85 * X.x(), 0.9 * X.y(), X.z()); };
// Rolled onto a cylinder of radius 0.4 m and stretched 2% along its axis.
const Deformation kBent = [](const Vec3& X) {
  const double R = 0.4;
  return Vec3(R * std::sin(X.x() / R), 1.02 * X.y(), R * (1 - std::cos(X.x() / R)));
};

Type4Data elastic(TransverseModel model = TransverseModel::Condensed) {
  Type4Data d;
  const double E = 1e6, nu = 0.3;
  d.mu = E / (2 * (1 + nu));
  d.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  d.model = model;
  return d;
}

TEST(Type4Batch, EqualsScalarOnStretchedBentAndCompressedStates) {
  for (const auto& [name, f] : std::vector<std::pair<const char*, Deformation>>{
           {"stretched", kStretched}, {"compressed", kCompressed}, {"bent", kBent}})
    for (TransverseModel model : {TransverseModel::Condensed, TransverseModel::Rigid, TransverseModel::Given})
      for (unsigned seed : {1u, 2u, 3u}) {
        PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), seed);
        deform(p, f, seed + 10);
        const Type4Data d = elastic(model);
        EXPECT_LE(mismatch(run_batched(p, d), run_scalar(p, d)), 1e-12) << name << " model " << static_cast<int>(model);
      }
}

// Every compilation of the kernel this processor can run, called directly (the dispatcher picks only one):
// the build's baseline instruction set (SSE2 on x86-64, four lanes in two registers), AVX2 (four lanes) and
// AVX-512 (eight lanes), on a bent and damaged state.
TEST(Type4Batch, EveryInstructionSetBuildEqualsScalar) {
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 21);
  deform(p, kBent, 22);
  for (Vec3& x : p.x) x = Vec3(1.1 * x.x(), x.y(), x.z());
  for (double& s : p.sigma_f) s = 3e4;
  Type4Data d = elastic();
  d.fracturing = true;
  const Outcome scalar = run_scalar(p, d);
  std::vector<std::pair<const char*, BatchKernel>> kernels{{"generic", detail::type4_force_batch_generic}};
#if defined(SHELLFRAC_TYPE4_AVX2)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) kernels.emplace_back("avx2", detail::type4_force_batch_avx2);
  if (avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
    kernels.emplace_back("avx512", detail::type4_force_batch_avx512);
#endif
  for (const auto& [name, kernel] : kernels) EXPECT_LE(mismatch(run_batched(p, d, 0xffu, kernel), scalar), 1e-12) << name;
  double damaged = 0;
  for (double c : scalar.damage) damaged = std::max(damaged, c);
  EXPECT_GT(damaged, 0.0);
}

TEST(Type4Batch, EqualsScalarOnACurvedRationalPatch) {
  // The rational cylinder has non-constant weights: the basis derivatives carry the quotient rule.
  for (unsigned seed : {4u, 5u}) {
    PointSet p(nurbs::cylinder_segment(0.5, 1.0, 2.0, 6, 5), seed);
    deform(p, [](const Vec3& X) { return Vec3(1.05 * X.x(), X.y() - 0.1 * X.z(), 0.98 * X.z()); }, seed);
    EXPECT_LE(mismatch(run_batched(p, elastic()), run_scalar(p, elastic())), 1e-12);
  }
}

TEST(Type4Batch, EqualsScalarOnDamagedStates) {
  // Failure stress at a fraction of the stretched sheet's stress: lanes below sigma_f, softening and fully
  // damaged, with plane strain's transverse stress and with the monotone rule (stored damage 0.5).
  for (bool plane_strain : {false, true})
    for (bool monotone : {false, true}) {
      PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 7);
      deform(p, kStretched, 8);
      const double fractions[kType4Lanes] = {2.0, 0.9, 0.7, 0.5, 0.3, 0.2, 0.1, 0.05};
      for (int i = 0; i < kType4Lanes; ++i) {
        p.sigma_f[static_cast<size_t>(i)] = fractions[i] * 1e5;  // the stress of a 15% stretch is ~1e5 Pa
        p.H[static_cast<size_t>(i)] = 0.5 + 0.3 * i;
      }
      for (double& c : p.damage) c = monotone ? 0.5 : 0.0;
      Type4Data d = elastic();
      d.fracturing = true;
      d.plane_strain = plane_strain;
      d.monotone = monotone;
      if (plane_strain) d.model = TransverseModel::Rigid;
      const Outcome batched = run_batched(p, d), scalar = run_scalar(p, d);
      EXPECT_LE(mismatch(batched, scalar), 1e-12) << plane_strain << monotone;
      // the set-up reaches every branch of the damage law
      int undamaged = 0, softening = 0, broken = 0;
      for (double c : scalar.damage) (c == 0 ? undamaged : c == 1 ? broken : softening)++;
      if (!monotone) {
        EXPECT_GT(undamaged, 0);
        EXPECT_GT(softening, 0);
        EXPECT_GT(broken, 0);
      }
    }
}

// The kernel skips the principal split for lane groups whose stress bound is clearly below sigma_f
// (lane_surely_intact): uniform failure stresses from far above the stretched sheet's stress to just below it
// put whole groups on that path, on the full path, and mixed; the results must not tell them apart.
TEST(Type4Batch, EqualsScalarAcrossTheDamageThreshold) {
  for (double sigma_f : {4e5, 2e5, 1.3e5, 1.1e5, 1.0e5, 0.9e5})
    for (bool monotone : {false, true}) {
      PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 11);
      deform(p, kStretched, 12);
      for (double& s : p.sigma_f) s = sigma_f;
      for (double& h : p.H) h = 0.8;
      Type4Data d = elastic();
      d.fracturing = true;
      d.monotone = monotone;
      const Outcome batched = run_batched(p, d), scalar = run_scalar(p, d);
      EXPECT_LE(mismatch(batched, scalar), 1e-12) << sigma_f << " " << monotone;
      for (size_t k = 0; k < scalar.damage.size(); ++k) {
        if (scalar.damage[k] == 0) {
          EXPECT_EQ(batched.damage[k], 0.0) << sigma_f;
        }
      }
    }
}

TEST(Type4Batch, EqualsScalarOnPlasticStates) {
  // Steel-like moduli, 0.4% stretch and a yield stress that half of the lanes exceed (by their own
  // accumulated plastic strain, which raises the limit); the other half stay elastic.
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 9);
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> u(-1e-4, 1e-4);
  for (Vec3& x : p.x) x = Vec3(1.004 * x.x() + u(rng), 0.999 * x.y() + u(rng), x.z() + u(rng));
  Type4Data d;
  const double E = 2e11, nu = 0.3;
  d.mu = E / (2 * (1 + nu));
  d.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  d.plastic = true;
  d.plasticity = {true, 2.5e8, 5e9};
  for (size_t k = 0; k < p.alpha.size(); ++k) p.alpha[k] = (k / 3) % 2 ? 0.2 : 0.0;  // per point
  const Outcome batched = run_batched(p, d), scalar = run_scalar(p, d);
  EXPECT_LE(mismatch(batched, scalar), 1e-12);
  int yielded = 0;
  for (size_t k = 0; k < p.alpha.size(); ++k) yielded += scalar.alpha[k] != p.alpha[k];
  EXPECT_GT(yielded, 0);                                        // some layer points flowed
  EXPECT_LT(yielded, static_cast<int>(p.alpha.size()));          // and some stayed elastic
}

// MLS supports can be larger than any NURBS support (kType4MaxSupport): the scalar kernel takes a support
// of 150 entries, the point's own 9 followed by 141 entries with zero basis values, and gives exactly the
// forces of the 9-entry support on those 9 and zero on the rest (it wrote past a fixed array of 64 before).
TEST(Type4Scalar, SupportsLargerThanTheLaneLimitGiveTheSameForces) {
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 16);
  deform(p, kStretched, 17);
  const Type4Data d = p.data(elastic());
  const int n = p.n, big = 150;
  ASSERT_GT(big, kType4MaxSupport);
  std::vector<int> support(p.support[0]);
  std::vector<double> basis(p.basis[0]);
  support.resize(static_cast<size_t>(big), support[0]);
  basis.resize(static_cast<size_t>(6 * big), 0.0);
  std::vector<Vec3> small(static_cast<size_t>(n), Vec3::Zero()), large(static_cast<size_t>(big), Vec3::Zero());
  ASSERT_EQ(type4_point_force(d, 0, {n, p.support[0].data(), p.basis[0].data()}, false, 0.97, small.data()), kType4Ok);
  ASSERT_EQ(type4_point_force(d, 0, {big, support.data(), basis.data()}, false, 0.97, large.data()), kType4Ok);
  EXPECT_GT(max_norm(small), 0.0);
  for (int s = 0; s < big; ++s)
    EXPECT_EQ(large[static_cast<size_t>(s)], s < n ? small[static_cast<size_t>(s)] : Vec3::Zero()) << s;
}

TEST(Type4Batch, InactiveLanesKeepTheirState) {
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 12);
  deform(p, kStretched, 13);
  for (double& s : p.sigma_f) s = 1e3;  // every lane would damage
  Type4Data d = elastic();
  d.fracturing = true;
  const unsigned active = 0x5au;
  const Outcome batched = run_batched(p, d, active), scalar = run_scalar(p, d, active);
  EXPECT_LE(mismatch(batched, scalar), 1e-12);
  for (int i = 0; i < kType4Lanes; ++i)
    for (int l = 0; l < p.layers; ++l)
      EXPECT_EQ(batched.damage[static_cast<size_t>(i * p.layers + l)] > 0, ((active >> i) & 1u) != 0);
}

TEST(Type4Batch, ReportsDegenerateAndRunawayLanesAsTheScalarDoes) {
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 14);
  // collapse the sheet onto a line: every point degenerate
  PointSet flat = p;
  for (Vec3& x : flat.x) x = Vec3(x.x(), 0, 0);
  const Outcome b1 = run_batched(flat, elastic()), s1 = run_scalar(flat, elastic());
  for (int i = 0; i < kType4Lanes; ++i) {
    EXPECT_EQ(b1.status[static_cast<size_t>(i)], kType4Degenerate);
    EXPECT_EQ(s1.status[static_cast<size_t>(i)], kType4Degenerate);
  }
  // stretched 40 x 40 in area: past the runaway limit of 1000
  for (Vec3& x : p.x) x = Vec3(40 * x.x(), 40 * x.y(), x.z());
  const Outcome b2 = run_batched(p, elastic()), s2 = run_scalar(p, elastic());
  for (int i = 0; i < kType4Lanes; ++i) {
    EXPECT_EQ(b2.status[static_cast<size_t>(i)], kType4Runaway);
    EXPECT_EQ(s2.status[static_cast<size_t>(i)], kType4Runaway);
  }
}

// Whole patches: every control point force of the batched pass against the scalar pass, with 16 points per
// cell (batches aligned to cells) and 9 (batches straddling cells and thread ranges).
TEST(Type4Batch, PatchForcesEqualTheScalarKernel) {
  for (int per_direction : {4, 3}) {
    ShellMaterial m = test::material(1e6, 0.3, 0.02);
    m.fracture.enabled = true;
    m.fracture.failure_stress = 2e4;
    QuadratureRule rule;
    rule.points_per_direction = per_direction;
    ShellPatch batched(nurbs::cylinder_segment(0.5, 1.0, 2.0, 7, 5), m, rule);
    batched.set_brittleness(1.0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (auto& x : batched.x) x = 1.05 * x + Vec3(u(rng), u(rng), u(rng));
    ShellPatch scalar = batched, gathered = batched;
    scalar.set_force_kernel(ForceKernel::Scalar);
    gathered.set_force_kernel(ForceKernel::BatchedGathered);
    ASSERT_FALSE(batched.compute_forces().failed);
    ASSERT_FALSE(scalar.compute_forces().failed);
    ASSERT_FALSE(gathered.compute_forces().failed);
    // The lane-ordered rest metrics and volumes hold the same numbers as the gathered ones: equal forces.
    for (size_t i = 0; i < batched.force.size(); ++i) ASSERT_EQ(batched.force[i], gathered.force[i]) << "control point " << i;
    double worst = 0;
    for (size_t i = 0; i < batched.force.size(); ++i) worst = std::max(worst, (batched.force[i] - scalar.force[i]).norm());
    EXPECT_LE(worst, 1e-12 * max_norm(scalar.force)) << per_direction;
    EXPECT_GT(batched.max_damage(), 0.0);  // the damage law is exercised
    for (size_t k = 0; k < batched.damage_values().size(); ++k)
      EXPECT_NEAR(batched.damage_values()[k], scalar.damage_values()[k], 1e-12);
  }
}

}  // namespace
}  // namespace shellfrac::shell

namespace shellfrac::shell {
namespace {

// The scalar damage law against an independent Rankine evaluation: the largest eigenvalue of the 3x3
// Cauchy stress tau^{ab} g_a (x) g_b / det F (a symmetric eigen solver; the transverse direction adds 0, or
// tau33 under plane strain), then Eq. 2.28. States from well below to past sigma_f, both signs of the
// stress and sheared tangents: c within 1e-9 and exactly +0 wherever the effective stress is below sigma_f
// by more than 1e-9 relative (the pre-check skips the principal split there; the result must not change).
TEST(Type4Damage, ScalarDamageEqualsAnIndependentRankineEvaluation) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0), ratio(0.3, 1.6);
  size_t checked = 0, zero = 0, damaged = 0;
  for (int rep = 0; rep < 20000; ++rep) {
    const Vec3 g1(1.0 + 0.2 * u(rng), 0.3 * u(rng), 0.1 * u(rng)), g2(0.3 * u(rng), 1.0 + 0.2 * u(rng), 0.1 * u(rng));
    const InPlaneTensor tau{1e4 * u(rng), 1e4 * u(rng), 1e4 * u(rng)};
    const double detF = 1.0 + 0.3 * u(rng), tau33 = 1e4 * u(rng);
    const bool plane_strain = rep % 2 == 1;
    Eigen::Matrix3d T = tau.t11 * g1 * g1.transpose() + tau.t12 * (g1 * g2.transpose() + g2 * g1.transpose()) +
                        tau.t22 * g2 * g2.transpose();
    const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(T).eigenvalues().maxCoeff();
    const double effective = std::max(plane_strain ? tau33 : 0.0, largest) / detF;
    const double sigma_f = std::abs(effective) / ratio(rng) + 1.0, H = 0.5;
    double damage = 0.7, history = 0.2;  // the healing rule overwrites c; the history keeps its maximum
    Type4Data d;
    d.fracturing = true;
    d.damage = &damage;
    d.damage_history = &history;
    d.failure_stress = &sigma_f;
    d.brittleness = &H;
    type4_damaged_stress(d, tau, g1, g2, detF, 0, 0, plane_strain ? &tau33 : nullptr);
    const double want = rankine_damage(effective, sigma_f, H);
    ++checked;
    if (effective < sigma_f * (1.0 - 1e-9)) {
      EXPECT_EQ(damage, 0.0);
      EXPECT_FALSE(std::signbit(damage));
      ++zero;
    } else {
      EXPECT_NEAR(damage, want, 1e-9);
      damaged += want > 0;
    }
    EXPECT_EQ(history, std::max(0.2, damage));
  }
  EXPECT_EQ(checked, 20000u);
  EXPECT_GT(zero, 2000u);     // both paths are exercised
  EXPECT_GT(damaged, 2000u);
}

// A residual stiffness r (FractureParams::residual_stiffness, CD-MPM's g(c) floor) scales the tensile
// principal Cauchy stresses by 1 - (1 - r) c instead of 1 - c (thesis Eq. 2.30 with r = 0) and leaves the
// compressive ones alone. Checked against an independent eigen-decomposition of the 3x3 stress on random
// states past sigma_f (fully damaged and softening), to 1e-9 of the stress scale.
TEST(Type4Damage, ResidualStiffnessKeepsItsShareOfTheTensileStress) {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r = 0.01, H = 0.5;
  auto tensor = [](const InPlaneTensor& t, const Vec3& g1, const Vec3& g2) -> Eigen::Matrix3d {
    return t.t11 * g1 * g1.transpose() + t.t12 * (g1 * g2.transpose() + g2 * g1.transpose()) +
           t.t22 * g2 * g2.transpose();
  };
  int full = 0, softening = 0;
  for (int rep = 0; rep < 2000; ++rep) {
    const Vec3 g1(1.0 + 0.2 * u(rng), 0.3 * u(rng), 0.1 * u(rng)), g2(0.3 * u(rng), 1.0 + 0.2 * u(rng), 0.1 * u(rng));
    const InPlaneTensor tau{1e4 * u(rng), 1e4 * u(rng), 1e4 * u(rng)};
    const Eigen::Matrix3d T = tensor(tau, g1, g2);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(T);
    const double largest = eig.eigenvalues().maxCoeff();
    if (largest <= 1.0) continue;
    // sigma_f at a tenth (fully damaged) or 0.9 (softening) of the effective stress (det F = 1)
    const double sigma_f = largest * (rep % 2 ? 0.1 : 0.9);
    double damage = 0, history = 0;
    Type4Data d;
    d.fracturing = true;
    d.residual = r;
    d.damage = &damage;
    d.damage_history = &history;
    d.failure_stress = &sigma_f;
    d.brittleness = &H;
    const InPlaneTensor got = type4_damaged_stress(d, tau, g1, g2, 1.0, 0, 0, nullptr);
    const double c = rankine_damage(largest, sigma_f, H);
    ASSERT_NEAR(damage, c, 1e-12);
    (c == 1.0 ? full : softening)++;
    Eigen::Vector3d lambda = eig.eigenvalues();
    for (int i = 0; i < 3; ++i)
      if (lambda[i] > 0) lambda[i] *= 1.0 - (1.0 - r) * c;
    const Eigen::Matrix3d want = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
    EXPECT_LE((tensor(got, g1, g2) - want).norm(), 1e-9 * T.norm()) << rep;
  }
  EXPECT_GT(full, 500);
  EXPECT_GT(softening, 500);
}

// The lane kernel applies the same residual share as the scalar reference.
TEST(Type4Batch, EqualsScalarWithAResidualStiffness) {
  PointSet p(nurbs::flat_patch(1.0, 1.0, 4, 4), 7);
  deform(p, kStretched, 8);
  const double fractions[kType4Lanes] = {2.0, 0.9, 0.7, 0.5, 0.3, 0.2, 0.1, 0.05};
  for (int i = 0; i < kType4Lanes; ++i) {
    p.sigma_f[static_cast<size_t>(i)] = fractions[i] * 1e5;
    p.H[static_cast<size_t>(i)] = 0.5 + 0.3 * i;
  }
  Type4Data d = elastic();
  d.fracturing = true;
  d.residual = 0.01;
  const Outcome batched = run_batched(p, d), scalar = run_scalar(p, d);
  EXPECT_LE(mismatch(batched, scalar), 1e-12);
  Type4Data thesis = d;
  thesis.residual = 0;
  EXPECT_GT(mismatch(run_scalar(p, thesis), scalar), 1e-6);  // the residual changes the forces
}

}  // namespace
}  // namespace shellfrac::shell
