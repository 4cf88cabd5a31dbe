// NACC plasticity (seed 001 sec. 6.2): the analytic return mapping against a Newton return
// of the same equations. Seed 001 reports a 2x speed-up of its analytic NACC kernel over an iterative
// (CCC) one; this measures ours on one core.
//
//   build/bench/bench_nacc --benchmark_counters_tabular=true
//
// states_per_s is the throughput (its inverse is the time per state).
// BM_Return: principal space only. BM_Project: with the SVD of F^E and the reconstruction, as a solver
// step runs it. range(0): 0 = analytic, 1 = Newton. The trial states are a fixed mix of the four
// branches (counters: share of each, Newton iterations per plastic state).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <random>

#include "brittle/nacc.hpp"
#include "brittle/split_elasticity.hpp"

namespace {

using namespace shellfrac::brittle;

struct Batch {
  double mu, kappa;
  NaccParams m;
  std::vector<Eigen::Vector3d> stretch;
  std::vector<Eigen::Matrix3d> F;
};

// E = 10 MPa, nu = 0.3; log stretches uniform in [-0.12, 0.12]; random rotations on both sides.
const Batch& batch() {
  static const Batch b = [] {
    Batch out;
    const double E = 1e7, nu = 0.3;
    out.mu = E / (2 * (1 + nu));
    out.kappa = bulk_modulus(out.mu, E * nu / ((1 + nu) * (1 - 2 * nu)));
    out.m.alpha0 = -0.04;
    out.m.beta = 0.3;
    out.m.xi = 3.0;
    out.m.friction = 1.2;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.12, 0.12);
    std::normal_distribution<double> g;
    for (int i = 0; i < 4096; ++i) {
      const Eigen::Vector3d s(std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng)));
      const Eigen::Matrix3d R1 = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
      const Eigen::Matrix3d R2 = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
      out.stretch.push_back(s);
      out.F.push_back(R1 * s.asDiagonal() * R2.transpose());
    }
    return out;
  }();
  return b;
}

void BM_Return(benchmark::State& state) {
  const Batch& b = batch();
  const bool newton = state.range(0) == 1;
  size_t branch[4] = {0, 0, 0, 0}, iterations = 0;
  double sink = 0;
  for (auto _ : state) {
    for (const Eigen::Vector3d& s : b.stretch) {
      const NaccState r = newton ? nacc_return_newton(s, b.m.alpha0, b.mu, b.kappa, b.m)
                                 : nacc_return(s, b.m.alpha0, b.mu, b.kappa, b.m);
      sink += r.stretch[0] + r.alpha;
      ++branch[static_cast<int>(r.branch)];
      iterations += static_cast<size_t>(r.iterations);
    }
  }
  benchmark::DoNotOptimize(sink);
  const double total = static_cast<double>(state.iterations() * b.stretch.size());
  state.counters["states_per_s"] = benchmark::Counter(total, benchmark::Counter::kIsRate);
  state.counters["shear_share"] = static_cast<double>(branch[3]) / total;
  state.counters["tip_share"] = static_cast<double>(branch[1] + branch[2]) / total;
  state.counters["elastic_share"] = static_cast<double>(branch[0]) / total;
  const double plastic = total - static_cast<double>(branch[0]);
  state.counters["newton_its"] = plastic > 0 ? static_cast<double>(iterations) / plastic : 0.0;
  state.SetLabel(newton ? "newton" : "analytic");
}
BENCHMARK(BM_Return)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_Project(benchmark::State& state) {
  const Batch& b = batch();
  const NaccSolve solve = state.range(0) == 1 ? NaccSolve::Newton : NaccSolve::Analytic;
  double sink = 0;
  for (auto _ : state) {
    for (const Eigen::Matrix3d& F0 : b.F) {
      Eigen::Matrix3d F = F0;
      double alpha = b.m.alpha0;
      nacc_project(F, alpha, b.mu, b.kappa, b.m, solve);
      sink += F(0, 0) + alpha;
    }
  }
  benchmark::DoNotOptimize(sink);
  const double total = static_cast<double>(state.iterations() * b.F.size());
  state.counters["states_per_s"] = benchmark::Counter(total, benchmark::Counter::kIsRate);
  state.SetLabel(solve == NaccSolve::Newton ? "newton" : "analytic");
}
BENCHMARK(BM_Project)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
