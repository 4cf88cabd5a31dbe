// Micro-benchmarks of the NURBS core: 1D basis with two derivatives, surface evaluation and the rational
// surface basis. Parameter points are precomputed (a fixed pseudo-random sweep) outside the timed loop.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "nurbs/bspline_basis.hpp"
#include "nurbs/patch_builders.hpp"

namespace {

using namespace shellfrac::nurbs;

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kPoints = 4096;  // power of two: cheap wrap-around

// Deterministic low-discrepancy-ish sweep of [0, 1] (additive recurrence with the golden ratio).
std::vector<double> sweep_1d(std::size_t n, double shift) {
  std::vector<double> t(n);
  double x = shift;
  for (std::size_t i = 0; i < n; ++i) {
    x += 0.6180339887498949;
    x -= static_cast<double>(static_cast<std::int64_t>(x));
    t[i] = x;
  }
  return t;
}

std::vector<std::pair<double, double>> sweep_2d(std::size_t n) {
  const std::vector<double> u = sweep_1d(n, 0.1), v = sweep_1d(n, 0.37);
  std::vector<std::pair<double, double>> uv(n);
  // Pair u with a shuffled v so that the points cover the square rather than a diagonal line.
  for (std::size_t i = 0; i < n; ++i) uv[i] = {u[i], v[(i * 1597) % n]};
  return uv;
}

void BM_BasisDerivs(benchmark::State& state) {
  const int degree = static_cast<int>(state.range(0));
  const KnotVector kv = KnotVector::open_uniform(degree, 40);
  const std::vector<double> us = sweep_1d(kPoints, 0.2);
  std::vector<double> out(static_cast<std::size_t>(3 * (degree + 1)));
  std::size_t i = 0;
  for (auto _ : state) {
    const int span = bspline_basis_derivs(kv, us[i], 2, out.data());
    benchmark::DoNotOptimize(span);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i = (i + 1) & (kPoints - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BasisDerivs)->Arg(2)->Arg(3)->ArgName("degree");

NurbsSurface make_surface(int which) {
  if (which == 0) return flat_patch(1.0, 1.0, 40, 40);
  return cylinder_segment(0.5, 2.0, 2 * kPi, 40, 40);  // rational
}

const char* surface_label(int which) { return which == 0 ? "flat 40x40" : "rational cylinder 40x40"; }

void BM_SurfaceEvaluate(benchmark::State& state) {
  const NurbsSurface s = make_surface(static_cast<int>(state.range(0)));
  const auto uv = sweep_2d(kPoints);
  std::size_t i = 0;
  for (auto _ : state) {
    SurfacePoint sp = s.evaluate(uv[i].first, uv[i].second);
    benchmark::DoNotOptimize(sp);
    i = (i + 1) & (kPoints - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(surface_label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_SurfaceEvaluate)->Arg(0)->Arg(1)->ArgName("rational");

void BM_SurfacePoint(benchmark::State& state) {
  const NurbsSurface s = make_surface(static_cast<int>(state.range(0)));
  const auto uv = sweep_2d(kPoints);
  std::size_t i = 0;
  for (auto _ : state) {
    Vec3 x = s.point(uv[i].first, uv[i].second);
    benchmark::DoNotOptimize(x);
    i = (i + 1) & (kPoints - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(surface_label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_SurfacePoint)->Arg(0)->Arg(1)->ArgName("rational");

void BM_RationalBasis(benchmark::State& state) {
  const NurbsSurface s = make_surface(static_cast<int>(state.range(0)));
  const auto uv = sweep_2d(kPoints);
  SurfaceBasis basis;
  std::size_t i = 0;
  for (auto _ : state) {
    s.rational_basis(uv[i].first, uv[i].second, basis);
    benchmark::DoNotOptimize(basis.R.data());
    benchmark::DoNotOptimize(basis.Rvv.data());
    benchmark::ClobberMemory();
    i = (i + 1) & (kPoints - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(surface_label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_RationalBasis)->Arg(0)->Arg(1)->ArgName("rational");

}  // namespace

BENCHMARK_MAIN();
