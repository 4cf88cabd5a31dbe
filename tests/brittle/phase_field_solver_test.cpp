// The CD-MPM phase field inside the brittle solver: a pulled and released bar keeps its broken set,
// and a notched beam breaks at its notch with crack surfaces extracted from the phase field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "brittle/crack_surface.hpp"
#include "brittle/solver.hpp"

namespace shellfrac::brittle {
namespace {

constexpr double kS = 0.0025, kDx = 0.005;

BrittleMaterial phase_field_material() {
  BrittleMaterial m;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.2;
  m.density = 1000;
  m.fracture_energy = 8;
  m.model = DamageModel::PhaseField;
  return m;
}

PhaseFieldOptions phase_field_options(PhaseFieldSolver solver) {
  PhaseFieldOptions o;
  o.mobility = 2000;
  o.solver = solver;
  return o;
}

// A 0.1 x 0.01 x 0.01 m bar with a one-cell notch at its middle, held at both ends by sticky boxes
// that pull apart at `speed`.
struct PulledBar {
  BrittleSolid solid;
  PulledBar() {
    solid.material = phase_field_material();
    solid.spacing = kS;
    std::vector<Vec3> pts;
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 40; ++i) {
          const Vec3 p(-0.05 + kS * (i + 0.5), kS * (j + 0.5), kS * (k + 0.5));
          if (std::abs(p.x()) < 0.002 && p.z() < 0.004) continue;
          pts.push_back(p);
        }
    solid.add_particles(pts, kS * kS * kS, Vec3::Zero());
    solid.set_strength({}, WeibullStrength{}, kDx);
  }
};

void add_grips(BrittleSolver& solver, double speed) {
  for (int side = -1; side <= 1; side += 2) {
    mpm::Collider grip;
    grip.shape = std::make_shared<mpm::Box>(Vec3(0.05 * side, 0.005, 0.005), Vec3(0.006, 0.02, 0.02));
    grip.motion.linear_velocity = Vec3(speed * side, 0, 0);
    grip.boundary = mpm::Boundary::Sticky;
    solver.add_collider(grip);
  }
}

TEST(PhaseFieldSolver, BrokenSetNeverShrinksUnderLoadAndUnload) {
  for (PhaseFieldSolver method : {PhaseFieldSolver::ConjugateGradient, PhaseFieldSolver::Cholmod}) {
    PulledBar bar;
    SolverOptions o;
    o.dx = kDx;
    o.two_fields = false;
    o.phase_field = phase_field_options(method);
    // Pull for 6 ms at 0.1 m/s per side, then hold the grips still: the ligament unloads.
    BrittleSolver pull(bar.solid, o);
    add_grips(pull, 0.1);
    std::vector<char> broken(bar.solid.size(), 0);
    std::vector<double> lowest = pull.phase();
    size_t peak = 0;
    auto check = [&](BrittleSolver& s) {
      for (size_t p = 0; p < bar.solid.size(); ++p) {
        const bool now = bar.solid.damage[p].c_his >= 1.0;
        ASSERT_FALSE(broken[p] && !now) << "particle " << p << " healed at t = " << s.time();
        broken[p] = now;
        // A new solver reads c back as 1 - (1 - c): allow that round-off, nothing more.
        ASSERT_LE(s.phase()[p], lowest[p] + 1e-15) << "c rose at particle " << p;
        lowest[p] = s.phase()[p];
      }
      peak = static_cast<size_t>(std::count(broken.begin(), broken.end(), 1));
    };
    while (pull.time() < 6e-3) {
      pull.step();
      check(pull);
    }
    const size_t loaded = peak;
    EXPECT_GT(loaded, 10u) << to_string(method);
    // Unload: a new solver over the same solid (as a fracture event reuses its particles) with resting
    // grips; the damage history carries over and the phase field must not recover.
    BrittleSolver rest(bar.solid, o);
    add_grips(rest, 0.0);
    for (int i = 0; i < 300; ++i) {
      rest.step();
      check(rest);
    }
    EXPECT_GE(peak, loaded);
    // Where the bar broke: at the notch plane, within two cells.
    double far = 0;
    for (size_t p = 0; p < bar.solid.size(); ++p)
      if (broken[p]) far = std::max(far, std::abs(bar.solid.rest[p].x()));
    EXPECT_LT(far, 2 * kDx) << to_string(method);
    EXPECT_EQ(pull.phase_field_totals().unconverged, 0u);
    if (method == PhaseFieldSolver::Cholmod) {
      EXPECT_GE(pull.phase_field_totals().analyses, 1u);
      EXPECT_LT(pull.phase_field_totals().analyses, pull.phase_field_totals().solves);
    }
  }
}

TEST(PhaseFieldSolver, SolvingEveryKStepsKeepsTheCrackingRate) {
  // Solved every k steps, each solve covers the k steps since the previous one, so c relaxes at the rate
  // M_c whatever k is. One backward-Euler step over k steps lags the k small ones (first order in k dt):
  // measured, the first particle breaks 3.78 ms into the pull with a solve every step and 4.14 ms (+9.4%)
  // every 10 steps. The criterion allows 15%. When each solve advanced c by one step only, it broke at
  // 6.13 ms (+62%), and at k = 50 never in 10 ms.
  auto first_break = [](size_t interval) {
    PulledBar bar;
    SolverOptions o;
    o.dx = kDx;
    o.two_fields = false;
    o.phase_field = phase_field_options(PhaseFieldSolver::ConjugateGradient);
    o.phase_field.interval = interval;
    BrittleSolver pull(bar.solid, o);
    add_grips(pull, 0.1);
    while (pull.time() < 10e-3) {
      pull.step();
      for (size_t p = 0; p < bar.solid.size(); ++p)
        if (bar.solid.damage[p].c_his >= 1.0) return pull.time();
    }
    return -1.0;
  };
  const double every = first_break(1), tenth = first_break(10);
  ASSERT_GT(every, 0);
  ASSERT_GT(tenth, 0) << "no particle broke in 10 ms with a solve every 10 steps";
  EXPECT_NEAR(tenth / every, 1.0, 0.15) << every << " s against " << tenth << " s";
}

TEST(PhaseFieldSolver, CracksAreExtractedFromThePhaseField) {
  PulledBar bar;
  SolverOptions o;
  o.dx = kDx;
  o.phase_field = phase_field_options(PhaseFieldSolver::ConjugateGradient);
  BrittleSolver solver(bar.solid, o);
  add_grips(solver, 0.1);
  while (solver.time() < 6e-3) solver.step();
  CrackExtractionOptions ex;
  ex.grid.spacing = kDx;
  const CrackExtraction crack = solver.update_crack(ex);
  ASSERT_FALSE(crack_surface_mesh(crack).triangles.empty());
  // The extracted surface spans the bar's cross-section at the notch plane.
  const TriMesh mesh = crack_surface_mesh(crack);
  double lo = 1, hi = -1;
  for (const Vec3& v : mesh.positions) {
    EXPECT_LT(std::abs(v.x()), 3 * kDx);
    lo = std::min(lo, v.z()), hi = std::max(hi, v.z());
  }
  EXPECT_GT(hi - lo, 0.005);
  EXPECT_TRUE(solver.sides().active());
}

}  // namespace
}  // namespace shellfrac::brittle
