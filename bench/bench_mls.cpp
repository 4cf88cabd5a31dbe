// MLS basis build rate (values + first + second derivatives) per evaluation point (thesis sec. 4.6).
#include <benchmark/benchmark.h>

#include <functional>
#include <random>
#include <vector>

#include "shell/mls_basis.hpp"

namespace {

using shellfrac::shell::AlwaysVisible;
using shellfrac::shell::ControlGrid;
using shellfrac::shell::MlsBasis;
using shellfrac::shell::MlsSettings;

// Open quadratic knot vector with `cells` spans on [0, 1]: Greville points 0, l/2, 3l/2, ..., 1.
ControlGrid make_grid(int cells) {
  ControlGrid g;
  const double l = 1.0 / cells;
  for (int i = 0; i < cells + 2; ++i) {
    const double x = i == 0 ? 0.0 : (i == cells + 1 ? 1.0 : (i - 0.5) * l);
    g.u.push_back(x);
    g.v.push_back(x);
  }
  g.cell_u = g.cell_v = l;
  return g;
}

// A slit {u = 0.5, v < 0.5} as a segment-crossing test: the cheapest crack a caller could have.
bool slit_visible(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double fa = a.x() - 0.5, fb = b.x() - 0.5;
  if (fa * fb >= 0.0) return true;
  const double t = fa / (fa - fb);
  const double v = a.y() + t * (b.y() - a.y());
  return !(v >= 0.0 && v < 0.5);
}

// Evaluation points: uniform over the patch, or in the band |u - 0.5| < 2 l below the slit tip
// (where MLS is used in practice).
std::vector<Eigen::Vector2d> make_points(int n, int cells, bool near_slit) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector2d> pts;
  for (int k = 0; k < n; ++k) {
    if (near_slit) {
      pts.emplace_back(0.5 + (2.0 * unit(rng) - 1.0) * 2.0 / cells, 0.5 * unit(rng));
    } else {
      pts.emplace_back(unit(rng), unit(rng));
    }
  }
  return pts;
}

template <class Visible>
void run(benchmark::State& state, Visible visible, bool near_slit) {
  const int cells = static_cast<int>(state.range(0));
  const ControlGrid grid = make_grid(cells);
  const std::vector<Eigen::Vector2d> pts = make_points(4096, cells, near_slit);
  MlsBasis basis;
  const MlsSettings settings;
  double support = 0.0, factor = 0.0;
  std::size_t i = 0;
  for (auto _ : state) {
    const bool ok = shellfrac::shell::mls_basis(pts[i], grid, visible, settings, basis);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(basis.R22.data());
    support += basis.size();
    factor += basis.factor;
    i = (i + 1) % pts.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["support"] = support / static_cast<double>(state.iterations());
  state.counters["factor"] = factor / static_cast<double>(state.iterations());
}

void BM_MlsNoCrack(benchmark::State& state) { run(state, AlwaysVisible{}, false); }
void BM_MlsSlit(benchmark::State& state) { run(state, slit_visible, true); }
void BM_MlsSlitStdFunction(benchmark::State& state) {
  const std::function<bool(const Eigen::Vector2d&, const Eigen::Vector2d&)> visible = slit_visible;
  run(state, visible, true);
}

}  // namespace

BENCHMARK(BM_MlsNoCrack)->Arg(100)->Arg(1000);
BENCHMARK(BM_MlsSlit)->Arg(100)->Arg(1000);
BENCHMARK(BM_MlsSlitStdFunction)->Arg(100);

BENCHMARK_MAIN();
