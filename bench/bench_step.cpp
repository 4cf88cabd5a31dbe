// One full simulation step of scenes/benchmark-sheet.json (1 m^2, 100 x 100 cells: 10,404 control
// points, 10,000 shear particles, 480,000 quadrature points), the size of a row of thesis Fig. 4.10,
// and of scenes/benchmark-tear.json: the same sheet fracturing (damage at every point) with a crack
// across half of it (MLS bases, phantom nodes and contact along the crack). Reports
// quadrature-point-steps per second and the per-stage split.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <map>

#include "scene/build.hpp"
#include "sim/simulation.hpp"

namespace {

using shellfrac::sim::Simulation;

void run_steps(benchmark::State& state, const char* scene_file) {
  const int threads = static_cast<int>(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const auto scene = shellfrac::scene::load_model(scene_file);
  Simulation sim(scene);
  const double dt = sim.stable_dt();
  for (int i = 0; i < 5; ++i) sim.step(dt);  // warm up: the sheet starts to sag
  std::map<std::string, double> before;
  for (const auto& [name, seconds] : sim.timer().seconds()) before[name] = seconds;
  for (auto _ : state) sim.step(dt);
  const double qp = static_cast<double>(sim.num_quadrature_points());
  state.SetItemsProcessed(static_cast<int64_t>(qp) * state.iterations());
  state.counters["qp_steps_per_s_per_core"] =
      benchmark::Counter(qp * static_cast<double>(state.iterations()) / threads, benchmark::Counter::kIsRate);
  for (const auto& [name, total] : sim.timer().seconds())
    state.counters["ms_" + name] = 1e3 * (total - before[name]) / static_cast<double>(state.iterations());
}

void BM_FullStep(benchmark::State& state) { run_steps(state, SHELLFRAC_SOURCE_DIR "/scenes/benchmark-sheet.json"); }
void BM_TearingStep(benchmark::State& state) { run_steps(state, SHELLFRAC_SOURCE_DIR "/scenes/benchmark-tear.json"); }
BENCHMARK(BM_FullStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TearingStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace


BENCHMARK_MAIN();
