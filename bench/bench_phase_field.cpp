// Cost of CD-MPM's non-local phase field against the thesis's local Rankine damage: wall
// time per brittle step on a stretched cube of n^3 particles (two per cell and axis, single velocity
// field), for local damage, the phase field with matrix-free CG, and the phase field with CHOLMOD.
//
//   build/bench/bench_phase_field --benchmark_counters_tabular=true
//
// range(0): the cube's side in particles; range(1): 0 = Rankine, 1 = phase field + CG, 2 = phase field
// + CHOLMOD. Counters: ms per step and of the phase-field stage, CG iterations per solve, unknowns.
// BM_PhaseFieldInterval: the CG phase field solved every 1, 5 or 10 steps at 512K particles.
// BM_PhaseFieldOperator: its operator alone, in lattice and in shuffled particle order.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "brittle/phase_field.hpp"
#include "brittle/solid_grid.hpp"

#include "brittle/solver.hpp"

namespace {

using namespace shellfrac::brittle;

BrittleSolid stretched_cube(int n, double s, DamageModel model) {
  BrittleSolid solid;
  solid.material.youngs_modulus = 1e7;
  solid.material.poisson_ratio = 0.2;
  solid.material.density = 1000;
  solid.material.failure_stress = 1e5;
  solid.material.fracture_energy = 8;
  solid.material.model = model;
  solid.spacing = s;
  std::vector<Vec3> pts;
  pts.reserve(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) pts.emplace_back(s * (i + 0.5), s * (j + 0.5), s * (k + 0.5));
  solid.add_particles(pts, s * s * s, Vec3::Zero());
  solid.set_strength({}, WeibullStrength{}, 2 * s);
  // Stretching along x at 2 /s: tension everywhere, so damage and Psi^H evolve in every particle.
  const double mid = 0.5 * n * s;
  for (size_t p = 0; p < solid.size(); ++p) solid.particles.v[p] = Vec3(2.0 * (solid.rest[p].x() - mid), 0, 0);
  return solid;
}

void damage_step(benchmark::State& state, int n, int mode, size_t interval) {
  const double s = 0.0025;
  BrittleSolid solid = stretched_cube(n, s, mode == 0 ? DamageModel::Rankine : DamageModel::PhaseField);
  SolverOptions o;
  o.dx = 2 * s;
  o.two_fields = false;
  o.phase_field.mobility = 2000;
  o.phase_field.solver = mode == 2 ? PhaseFieldSolver::Cholmod : PhaseFieldSolver::ConjugateGradient;
  o.phase_field.interval = interval;
  BrittleSolver solver(solid, o);
  for (int warm = 0; warm < 2; ++warm) solver.step();
  const StageTimes before = solver.times();
  const PhaseFieldTotals pf_before = solver.phase_field_totals();
  for (auto _ : state) solver.step();
  const StageTimes& after = solver.times();
  const PhaseFieldTotals& pf = solver.phase_field_totals();
  const double steps = static_cast<double>(state.iterations());
  state.SetLabel(mode == 0 ? "rankine" : mode == 1 ? "phase_field_cg" : "phase_field_cholmod");
  state.counters["particles"] = static_cast<double>(solid.size());
  state.counters["ms_per_step"] = 1e3 * (after.total() - before.total()) / steps;
  state.counters["phase_field_ms"] = 1e3 * (after.phase_field - before.phase_field) / steps;
  state.counters["p2g_ms"] = 1e3 * (after.p2g - before.p2g) / steps;
  const double solves = static_cast<double>(pf.solves - pf_before.solves);
  state.counters["cg_iterations"] = solves > 0 ? static_cast<double>(pf.iterations - pf_before.iterations) / solves : 0;
  state.counters["unknowns"] = static_cast<double>(pf.unknowns);
  state.counters["analyses"] = static_cast<double>(pf.analyses - pf_before.analyses);
}
void BM_DamageStep(benchmark::State& state) {
  damage_step(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 1);
}
// The phase field with CG solved every range(1) steps (phase_field.interval; each solve covers the steps
// since the last one), at 512K particles: 20 steps per measurement, so that every run averages whole
// intervals.
void BM_PhaseFieldInterval(benchmark::State& state) {
  damage_step(state, 80, 1, static_cast<size_t>(state.range(0)));
}
BENCHMARK(BM_PhaseFieldInterval)->Arg(1)->Arg(5)->Arg(10)->Iterations(20)->Unit(benchmark::kMillisecond)->UseRealTime();
// The phase-field operator alone (one y = (M + H) x, the CG's inner pass, after one solve has assembled
// the system) at n^3 particles two per cell and axis: range(0) = n, range(1) = 1 to shuffle the particle
// order (a solid sampled in no spatial order) or 0 (lattice order, as solids are sampled). Counter: ns
// per particle per pass.
void BM_PhaseFieldOperator(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const double s = 0.0025, dx = 2 * s;
  std::vector<GVec3> x;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) x.emplace_back(s * (i + 0.5), s * (j + 0.5), s * (k + 0.5));
  if (state.range(1) == 1) std::shuffle(x.begin(), x.end(), std::mt19937(7));
  std::vector<double> volume(x.size(), s * s * s), history(x.size()), c(x.size(), 1.0);
  for (size_t p = 0; p < x.size(); ++p) history[p] = 50.0 * (1.0 + std::sin(37.0 * x[p].x()));
  const PhaseFieldParticles view{x.size(), x.data(), volume.data(), history.data(), c.data()};
  SolidGrid grid(dx);
  grid.rebuild(x.data(), x.size(), {}, false, size_t{8} << 30);
  PhaseFieldOptions o;
  o.mobility = 2000;
  PhaseFieldSystem system(o, 8.0, dx);
  system.solve(grid, view, 1e-5);
  std::vector<double> in(grid.num_nodes()), out;
  for (size_t i = 0; i < in.size(); ++i) in[i] = 1.0 + 0.01 * std::cos(0.1 * static_cast<double>(i));
  for (auto _ : state) {
    system.apply(grid, view, in, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["ns_per_particle"] =
      benchmark::Counter(static_cast<double>(x.size()) * 1e-9, benchmark::Counter::kIsIterationInvariantRate |
                                                                     benchmark::Counter::kInvert);
  state.counters["particles"] = static_cast<double>(x.size());
}
BENCHMARK(BM_PhaseFieldOperator)->ArgsProduct({{80}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

// 8K, 64K, 216K, 512K and 1M particles.
BENCHMARK(BM_DamageStep)
    ->ArgsProduct({{20, 40, 60, 80, 100}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
