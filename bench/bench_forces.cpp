// The shell force pass alone (Type IV kernel, scatter, Type III, gather) on scenes/benchmark-sheet.json after
// the warm-up of bench_step (the sheet sagging under gravity), with the batched kernel (first argument 1), the
// same gathering its rest metrics and volumes per lane (2) or the scalar reference (0), at 1 or 2 threads:
// the kernels compared in one process.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "scene/build.hpp"
#include "shell/shell_patch.hpp"
#include "sim/simulation.hpp"

namespace {

void BM_ShellForces(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const auto scene = shellfrac::scene::load_model(SHELLFRAC_SOURCE_DIR "/scenes/benchmark-sheet.json");
  shellfrac::sim::Simulation sim(scene);
  const double dt = sim.stable_dt();
  for (int i = 0; i < 5; ++i) sim.step(dt);
  shellfrac::shell::ShellPatch patch = sim.world().shell(0);
  using shellfrac::shell::ForceKernel;
  const ForceKernel kernel = state.range(0) == 0 ? ForceKernel::Scalar
                             : state.range(0) == 1 ? ForceKernel::Batched
                                                   : ForceKernel::BatchedGathered;
  patch.set_force_kernel(kernel);
  for (auto _ : state) benchmark::DoNotOptimize(patch.compute_forces().failed);
  const double qp = static_cast<double>(patch.num_quadrature_points());
  state.counters["qp_per_s_per_core"] =
      benchmark::Counter(qp * static_cast<double>(state.iterations()) / threads, benchmark::Counter::kIsRate);
  state.SetLabel(kernel == ForceKernel::Scalar ? std::string("scalar")
                 : std::string(shellfrac::shell::type4_batch_isa()) + (kernel == ForceKernel::BatchedGathered ? " gathered" : ""));
}
BENCHMARK(BM_ShellForces)->ArgsProduct({{0, 1, 2}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
