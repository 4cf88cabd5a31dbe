// The sparse grid's per-step rebuild (mpm/sparse_grid.cpp): the particles of a 1 m^2 sheet of 100 x 100
// cells (control points and shear particles, as in scenes/benchmark-sheet.json) moving a little every
// step, rebuilt with a fresh block layout every step (layout reuse 0) against the default, which keeps the
// layout while it still holds every particle's stencil, and the bins and entry order while no particle
// changes block.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "mpm/sparse_grid.hpp"

namespace {

using namespace shellfrac::mpm;

void BM_GridRebuild(benchmark::State& state) {
  const int reuse = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  std::vector<Vec3> x, v;
  std::vector<double> m;
  const int n = 100;
  for (int i = 0; i <= n; ++i)  // control points on the knots, shear particles at the cell centres
    for (int j = 0; j <= n; ++j) x.emplace_back(0.01 * i, 1.0, 0.01 * j);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) x.emplace_back(0.01 * (i + 0.5), 1.0, 0.01 * (j + 0.5));
  v.assign(x.size(), Vec3::Zero());
  m.assign(x.size(), 1e-5);
  ParticleSet set;
  set.count = x.size();
  set.position = x.data();
  set.velocity = v.data();
  set.mass = m.data();
  const std::vector<ParticleSet> sets{set};
  SparseGrid grid(0.01);
  grid.set_layout_reuse(reuse);
  long step = 0;
  for (auto _ : state) {
    // A sagging, swinging sheet: each point moves about 1e-4 m (a hundredth of a cell) per step.
    state.PauseTiming();
    for (size_t p = 0; p < x.size(); ++p) x[p].y() -= 1e-4 * std::sin(3.0 * x[p].x() + 1e-3 * static_cast<double>(step));
    ++step;
    state.ResumeTiming();
    grid.rebuild(sets);
  }
  state.SetItemsProcessed(static_cast<int64_t>(x.size()) * state.iterations());
  // Which path the rebuilds took (SparseGrid::RebuildCounts): bins kept, particles binned again on the
  // kept layout, or a new layout.
  const SparseGrid::RebuildCounts& c = grid.rebuild_counts();
  const double all = static_cast<double>(c.kept_bins + c.rebinned + c.kept_layout_rebinned_afresh + c.fresh_layouts);
  state.counters["kept_bins"] = static_cast<double>(c.kept_bins) / all;
  state.counters["rebinned"] = static_cast<double>(c.rebinned) / all;
  state.counters["fresh"] = static_cast<double>(c.fresh_layouts) / all;
}
BENCHMARK(BM_GridRebuild)
    ->ArgsProduct({{0, SparseGrid::kDefaultLayoutReuse}, {1, 2}})
    ->ArgNames({"reuse", "threads"})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
