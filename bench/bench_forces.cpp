// The shell force pass alone (Type IV kernel, scatter, Type III, gather) on scenes/benchmark-sheet.json after
// the warm-up of bench_step (the sheet sagging under gravity), with the batched kernel (first argument 1), the
// same gathering its rest metrics and volumes per lane (2) or the scalar reference (0), at 1 or 2 threads:
// the kernels compared in one process. BM_CrackedShellForces does the same on a patch with many MLS points.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "nurbs/patch_builders.hpp"
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

// A shattered pane: a 48 x 48 flat patch (3 mm glass, fracturing) with twelve cracks through a common
// point and a ring around it, so that a large share of the points have MLS bases of many sizes, stretched
// by 4% with a random jitter. First argument: MLS points in lanes (1), by the scalar code with NURBS points
// in lanes (2), or everything scalar (0); second: threads.
void BM_CrackedShellForces(benchmark::State& state) {
  using namespace shellfrac;
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  shell::ShellMaterial m;
  const double E = 7e10, nu = 0.22;
  m.mu = E / (2 * (1 + nu));
  m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  m.density = 2500;
  m.thickness = 0.003;
  m.fracture.enabled = true;
  m.fracture.failure_stress = 5e6;
  shell::ShellPatch patch(nurbs::flat_patch(0.3, 0.3, 48, 48), m);
  patch.set_brittleness(1.0);
  crack2d::CrackGraph graph;
  const Eigen::Vector2d centre(0.47, 0.52);
  const int hub = graph.add_vertex(centre);
  int previous = -1, first = -1;
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * M_PI * (k + 0.3) / 12;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const int ring = graph.add_vertex(centre + 0.2 * dir), tip = graph.add_vertex(centre + 0.45 * dir);
    graph.add_edge(hub, ring);
    graph.add_edge(ring, tip);
    if (previous >= 0) graph.add_edge(previous, ring);
    previous = ring;
    if (first < 0) first = ring;
  }
  graph.add_edge(previous, first);
  crack2d::CrackIndex index;
  index.add_edges(graph, 0);
  patch.update_crack(index, 0, shell::MlsSettings{});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-5, 1e-5);
  for (auto& x : patch.x) x = 1.04 * x + shell::Vec3(jitter(rng), jitter(rng), jitter(rng));
  using shell::ForceKernel;
  const ForceKernel kernel = state.range(0) == 0 ? ForceKernel::Scalar
                             : state.range(0) == 1 ? ForceKernel::Batched
                                                   : ForceKernel::BatchedScalarMls;
  patch.set_force_kernel(kernel);
  for (auto _ : state) benchmark::DoNotOptimize(patch.compute_forces().failed);
  state.counters["mls_points"] = static_cast<double>(patch.num_mls_points());
  state.counters["points"] = static_cast<double>(patch.num_quadrature_points());
  state.SetLabel(kernel == ForceKernel::Scalar ? "scalar" : kernel == ForceKernel::Batched ? "MLS in lanes" : "MLS scalar");
}
BENCHMARK(BM_CrackedShellForces)->ArgsProduct({{0, 1, 2}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
