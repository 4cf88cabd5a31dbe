// Micro-benchmarks of the crack2d layer: the visibility query and one consistent extraction.
#include "crack2d/consistent_extraction.hpp"
#include "crack2d/crack_index.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

using namespace shellfrac::crack2d;

namespace {

// A 1000-segment crack: an Archimedean spiral over most of the unit patch.
CrackGraph spiral_crack(int segments) {
  CrackGraph g;
  int previous = -1;
  for (int i = 0; i <= segments; ++i) {
    const double theta = 10.0 * M_PI * i / segments;
    const double r = 0.03 + 0.08 * theta / (2.0 * M_PI);
    const int v = g.add_vertex(Point(0.5 + r * std::cos(theta), 0.5 + r * std::sin(theta)));
    if (previous >= 0) g.add_edge(previous, v);
    previous = v;
  }
  return g;
}

// MLS-support-sized query segments (length up to 0.03, i.e. about three cells of a 100-cell patch).
std::vector<Segment> query_segments(int count) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0), d(-0.03, 0.03);
  std::vector<Segment> q;
  for (int i = 0; i < count; ++i) {
    const Point a(u(rng), u(rng));
    q.push_back({a, a + Point(d(rng), d(rng))});
  }
  return q;
}

void BM_CrackIndexCrosses(benchmark::State& state) {
  const CrackGraph g = spiral_crack(static_cast<int>(state.range(0)));
  CrackIndex index;
  index.rebuild(g);
  const std::vector<Segment> queries = query_segments(1 << 16);
  size_t i = 0, hits = 0;
  for (auto _ : state) {
    const Segment& s = queries[i++ & (queries.size() - 1)];
    hits += index.crosses(s.a, s.b);
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
  state.counters["cells"] = index.cells_x() * index.cells_y();
}
BENCHMARK(BM_CrackIndexCrosses)->Arg(1000);

void BM_CrackIndexRebuild(benchmark::State& state) {
  const CrackGraph g = spiral_crack(static_cast<int>(state.range(0)));
  CrackIndex index;
  for (auto _ : state) {
    index.rebuild(g);
    benchmark::DoNotOptimize(index.num_segments());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CrackIndexRebuild)->Arg(1000);

// A 100 x 100-cell patch with 4 x 4 Gauss-Legendre samples per cell (160 000 sample points) and a
// slanted damaged band about 8 samples wide and 0.7 long.
void BM_ConsistentExtraction(benchmark::State& state) {
  const int cells = 100;
  const double cell = 1.0 / cells;
  const double gauss[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
  std::vector<Point> points;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i)
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) points.emplace_back((i + gauss[a]) * cell, (j + gauss[b]) * cell);
  const double spacing = cell / 4;
  const Segment axis{Point(0.0, 0.4), Point(0.7, 0.6)};
  std::vector<unsigned char> damaged(points.size());
  size_t count = 0;
  for (size_t k = 0; k < points.size(); ++k) count += damaged[k] = point_segment_distance(points[k], axis) < 4 * spacing;
  ExtractionStats stats;
  size_t edges = 0;
  for (auto _ : state) {
    ConsistentCrackExtractor extractor(Box{Point(0, 0), Point(1, 1)}, spacing);
    stats = extractor.extract(points, damaged);
    edges = extractor.graph().num_edges();
  }
  state.counters["samples"] = static_cast<double>(points.size());
  state.counters["damaged"] = static_cast<double>(count);
  state.counters["seeds"] = static_cast<double>(stats.seeds);
  state.counters["edges"] = static_cast<double>(edges);
  state.counters["components_linked"] = static_cast<double>(stats.branch_links + stats.tip_bridges);
}
BENCHMARK(BM_ConsistentExtraction)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
