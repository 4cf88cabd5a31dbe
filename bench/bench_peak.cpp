// This machine's ceilings for the roofline in docs/performance.md: the double-precision FMA peak of one
// core (independent multiply-add chains, enough of them to hide the FMA latency) and the memory bandwidth
// of the STREAM triad a = b + s c on arrays far larger than the caches.
//
// Compiled with -mavx2 -mfma on x86-64 (bench/CMakeLists.txt), the instruction set the Type IV kernel
// dispatches to; elsewhere with the build's baseline.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

namespace {

typedef double Quad __attribute__((vector_size(4 * sizeof(double))));

// 12 chains x 4 doubles x 2 flops per multiply-add per iteration.
void BM_FmaPeak(benchmark::State& state) {
  constexpr int kChains = 12;
  Quad acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = Quad{} + 1.0 + 1e-3 * c;
  Quad a = Quad{} + 0.999999, b = Quad{} + 1e-7;
  for (auto _ : state) {
    for (int it = 0; it < 1000; ++it)
      for (int c = 0; c < kChains; ++c) acc[c] = acc[c] * a + b;
    benchmark::DoNotOptimize(acc);
    benchmark::ClobberMemory();
  }
  const double flops = 1000.0 * kChains * 4 * 2;
  state.counters["flops"] = benchmark::Counter(flops * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FmaPeak)->Threads(1)->Threads(2)->UseRealTime();

// STREAM triad on 3 x 64 MiB: bytes counted as 2 reads + 1 write (24 per element; the write-allocate read
// of `a` is extra traffic the counter leaves out, as STREAM does).
void BM_Triad(benchmark::State& state) {
  const size_t n = size_t{8} << 20;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const double s = 3.0;
  for (auto _ : state) {
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::ClobberMemory();
  }
  state.counters["bytes"] = benchmark::Counter(24.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate, benchmark::Counter::kIs1024);
}
BENCHMARK(BM_Triad)->Threads(1)->Threads(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
