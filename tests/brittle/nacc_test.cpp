// NACC plasticity (seed 001, sec. 6.2): the analytic return lands on the yield surface, keeps volume in
// the shear case, matches an independent Newton solve of the same equations, and hardens the way
// sec. 6.2.3 says.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "brittle/nacc.hpp"
#include "brittle/split_elasticity.hpp"

namespace shellfrac::brittle {
namespace {

struct Fixture {
  double mu, kappa;
  NaccParams m;
};

// A stiff, cohesive solid: E = 10 MPa, nu = 0.3; p0(alpha0) = kappa sinh(0.12) = 1.0 MPa.
Fixture stiff_solid() {
  const double E = 1e7, nu = 0.3;
  Fixture f;
  f.mu = E / (2 * (1 + nu));
  f.kappa = bulk_modulus(f.mu, E * nu / ((1 + nu) * (1 - 2 * nu)));
  f.m.alpha0 = -0.04;
  f.m.beta = 0.3;
  f.m.xi = 3.0;
  f.m.friction = 1.2;
  return f;
}

double yield_scale(double p0, const NaccParams& m) {
  const double a = 0.5 * (1 + m.beta) * p0;
  return m.friction * m.friction * a * a;
}

// Trial stretches exp(e), e uniform in [-0.12, 0.12] per axis, sorted decreasing as an SVD returns them.
std::vector<Eigen::Vector3d> trial_stretches(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.12, 0.12);
  std::vector<Eigen::Vector3d> out(n);
  for (auto& s : out) {
    s = Eigen::Vector3d(std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng)));
    std::sort(s.data(), s.data() + 3, std::greater<>());
  }
  return out;
}

TEST(Nacc, ReturnLandsOnTheYieldSurfaceInEveryCase) {
  const Fixture f = stiff_solid();
  const double p0 = nacc_p0(f.m.alpha0, f.kappa, f.m);
  int counts[4] = {0, 0, 0, 0};
  double worst = 0;
  for (const Eigen::Vector3d& s : trial_stretches(4000, 1)) {
    const NaccState r = nacc_return(s, f.m.alpha0, f.mu, f.kappa, f.m);
    ++counts[static_cast<int>(r.branch)];
    const Eigen::Vector2d pq = nacc_invariants(r.stretch, f.mu, f.kappa);
    const double y = nacc_yield(pq[0], pq[1], p0, f.m) / yield_scale(p0, f.m);
    if (r.branch == NaccCase::Elastic) {
      EXPECT_LE(y, 0.0);
      EXPECT_EQ(r.stretch, s);  // inside: untouched
      EXPECT_EQ(r.alpha, f.m.alpha0);
    } else {
      worst = std::max(worst, std::abs(y));
    }
  }
  // Criterion: residual <= 1e-10 (relative to the yield function's value at the centre).
  EXPECT_LE(worst, 1e-10);
  for (int c = 0; c < 4; ++c) EXPECT_GE(counts[c], 100) << "branch " << to_string(static_cast<NaccCase>(c)) << " barely sampled";
}

TEST(Nacc, ShearReturnKeepsVolumeAndTheDeviatorDirection) {
  const Fixture f = stiff_solid();
  int shear = 0;
  for (const Eigen::Vector3d& s : trial_stretches(4000, 2)) {
    const NaccState r = nacc_return(s, f.m.alpha0, f.mu, f.kappa, f.m);
    if (r.branch != NaccCase::Shear) continue;
    ++shear;
    // det F^P = det F / det F^E is unchanged when det F^E is: non-associated flow is isochoric.
    EXPECT_NEAR(r.stretch.prod() / s.prod(), 1.0, 1e-14);
    // dev(log stretch) of the returned state points the way the trial's deviatoric stress does.
    const Eigen::Vector3d bt = s.cwiseProduct(s), bn = r.stretch.cwiseProduct(r.stretch);
    const Eigen::Vector3d dt = (bt.array() - bt.sum() / 3).matrix(), dn = (bn.array() - bn.sum() / 3).matrix();
    EXPECT_NEAR(dt.dot(dn) / (dt.norm() * dn.norm()), 1.0, 1e-12);
    EXPECT_LT(dn.norm(), dt.norm());
  }
  EXPECT_GE(shear, 100);
}

TEST(Nacc, AnalyticReturnMatchesNewton) {
  const Fixture f = stiff_solid();
  double worst_stretch = 0, worst_alpha = 0;
  int max_it = 0;
  for (const Eigen::Vector3d& s : trial_stretches(4000, 3)) {
    // Part of the samples at a hardened and a softened state, so the ellipse's size varies too.
    for (double alpha : {f.m.alpha0, 2 * f.m.alpha0, 0.3 * f.m.alpha0}) {
      const NaccState a = nacc_return(s, alpha, f.mu, f.kappa, f.m);
      const NaccState n = nacc_return_newton(s, alpha, f.mu, f.kappa, f.m);
      ASSERT_EQ(a.branch, n.branch);
      worst_stretch = std::max(worst_stretch, (a.stretch - n.stretch).lpNorm<Eigen::Infinity>());
      worst_alpha = std::max(worst_alpha, std::abs(a.alpha - n.alpha));
      max_it = std::max(max_it, n.iterations);
    }
  }
  // Criterion: the two agree to 1e-10.
  EXPECT_LE(worst_stretch, 1e-10);
  EXPECT_LE(worst_alpha, 1e-10);
  EXPECT_LT(max_it, 60) << "Newton hit its iteration cap";
}

TEST(Nacc, HardeningFollowsSection623) {
  const Fixture f = stiff_solid();
  const double p0 = nacc_p0(f.m.alpha0, f.kappa, f.m), pc = 0.5 * (1 - f.m.beta) * p0;
  int checked = 0;
  for (const Eigen::Vector3d& s : trial_stretches(4000, 4)) {
    const NaccState r = nacc_return(s, f.m.alpha0, f.mu, f.kappa, f.m);
    const double p = nacc_invariants(s, f.mu, f.kappa)[0];
    const double da = r.alpha - f.m.alpha0;
    switch (r.branch) {
      case NaccCase::Elastic: EXPECT_EQ(da, 0.0); break;
      // Case 1: alpha += log(J_tr / J_new) with the tip at p0; J_new from p = -kappa/2 (J^2 - 1).
      case NaccCase::Compression:
        EXPECT_NEAR(da, std::log(s.prod() / std::sqrt(1 - 2 * p0 / f.kappa)), 1e-13);
        EXPECT_LT(da, 0.0);  // compression hardens
        break;
      case NaccCase::Tension:
        EXPECT_NEAR(da, std::log(s.prod() / std::sqrt(1 + 2 * f.m.beta * p0 / f.kappa)), 1e-13);
        EXPECT_GT(da, 0.0);  // tension softens
        break;
      case NaccCase::Shear:
        // Hardening on the compressive side of the centre, softening on the tensile side.
        if (p > pc) EXPECT_LT(da, 0.0);
        else EXPECT_GT(da, 0.0);
        break;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 4000);
  // Without hardening alpha never moves.
  NaccParams off = f.m;
  off.hardening = false;
  for (const Eigen::Vector3d& s : trial_stretches(500, 5))
    EXPECT_EQ(nacc_return(s, off.alpha0, f.mu, f.kappa, off).alpha, off.alpha0);
}

TEST(Nacc, BrokenMaterialCarriesNoStress) {
  // alpha >= 0: p0 = 0, the ellipse is the origin, and every trial returns to a stress-free rotation.
  const Fixture f = stiff_solid();
  for (const Eigen::Vector3d& s : trial_stretches(500, 6)) {
    const NaccState r = nacc_return(s, 0.0, f.mu, f.kappa, f.m);
    EXPECT_LE((r.stretch - Eigen::Vector3d::Ones()).lpNorm<Eigen::Infinity>(), 1e-14);
  }
  EXPECT_DOUBLE_EQ(nacc_damage(0.0, f.kappa, f.m), 1.0);
  EXPECT_DOUBLE_EQ(nacc_damage(f.m.alpha0, f.kappa, f.m), 0.0);
  EXPECT_DOUBLE_EQ(nacc_damage(2 * f.m.alpha0, f.kappa, f.m), 0.0);  // hardened reads as intact
  // Halfway in p0: sinh(xi (-alpha)) = sinh(0.12) / 2.
  const double half = -std::asinh(0.5 * std::sinh(0.12)) / f.m.xi;
  EXPECT_NEAR(nacc_damage(half, f.kappa, f.m), 0.5, 1e-14);
}

TEST(Nacc, ProjectRotatesBackWithTheSingularVectors) {
  // F = R1 diag(s) R2^T with random rotations: the projected F is R1 diag(return(s)) R2^T.
  const Fixture f = stiff_solid();
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  int plastic = 0;
  for (const Eigen::Vector3d& s : trial_stretches(300, 8)) {
    if (s[0] - s[1] < 1e-3 || s[1] - s[2] < 1e-3) continue;  // singular vectors need distinct values
    const Eigen::Matrix3d R1 = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    const Eigen::Matrix3d R2 = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    Eigen::Matrix3d F = R1 * s.asDiagonal() * R2.transpose();
    double alpha = f.m.alpha0;
    const NaccCase c = nacc_project(F, alpha, f.mu, f.kappa, f.m);
    const NaccState r = nacc_return(s, f.m.alpha0, f.mu, f.kappa, f.m);
    ASSERT_EQ(c, r.branch);
    plastic += c != NaccCase::Elastic;
    EXPECT_LE((F - R1 * r.stretch.asDiagonal() * R2.transpose()).lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_NEAR(alpha, r.alpha, 1e-14);
  }
  EXPECT_GE(plastic, 50);
}

TEST(Nacc, RefusesNonPhysicalParameters) {
  NaccParams m;
  EXPECT_EQ(m.validate(), "");
  m.alpha0 = 0.0;
  EXPECT_NE(m.validate().find("alpha0"), std::string::npos);
  m = NaccParams{};
  m.beta = -0.1;
  EXPECT_NE(m.validate().find("beta"), std::string::npos);
  m = NaccParams{};
  m.xi = 0;
  EXPECT_NE(m.validate().find("xi"), std::string::npos);
  m = NaccParams{};
  m.friction = std::nan("");
  EXPECT_NE(m.validate().find("friction"), std::string::npos);
}

}  // namespace
}  // namespace shellfrac::brittle
