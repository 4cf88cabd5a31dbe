// Phantom nodes near a crack (thesis sec. 4.7): partitioning the nodes a crack runs through into one
// copy per fragment side, and resolving contact between the copies (Eq. 4.22-4.26). Two sheets of
// particles meet along a 1 m crack, as in a torn 100 x 100-cell sheet (about 20 particles per cell row).
#include <benchmark/benchmark.h>

#include <random>

#include "mpm/phantom_nodes.hpp"
#include "mpm/sparse_grid.hpp"

namespace {

using namespace shellfrac::mpm;

struct Sheet {
  std::vector<Vec3> x, v;
  std::vector<double> m;
  std::vector<int> side;
  std::vector<unsigned char> near;
  ParticleSet set() {
    ParticleSet s;
    s.count = x.size();
    s.position = x.data();
    s.velocity = v.data();
    s.mass = m.data();
    return s;
  }
};

// A 1 m x 0.2 m strip of particles (spacing 0.005 m) split at y = 0.1; the halves press together.
Sheet torn_strip() {
  Sheet s;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> j(-0.0005, 0.0005);
  for (int i = 0; i < 200; ++i)
    for (int k = 0; k < 40; ++k) {
      const double y = 0.0025 + 0.005 * k;
      const int side = y < 0.1 ? 0 : 1;
      s.x.emplace_back(0.0025 + 0.005 * i, y, 0.5 + j(rng));
      s.v.emplace_back(0.0, side == 0 ? 0.2 : -0.2, 0.0);
      s.m.push_back(1e-4);
      s.side.push_back(side);
      s.near.push_back(std::abs(y - 0.1) < 0.03 ? 1 : 0);  // particles in MLS supports near the crack
    }
  return s;
}

void BM_PartitionNodes(benchmark::State& state) {
  Sheet s = torn_strip();
  std::vector<ParticleSet> sets{s.set()};
  SparseGrid grid(0.01);
  grid.rebuild(sets);
  const Connectivity connected = [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return s.side[a] == s.side[b]; };
  size_t split = 0;
  for (auto _ : state) {
    const PhantomLayout layout = partition_nodes(grid, sets, {PartitionRole{FieldKind::Shell, s.near.data()}}, connected);
    split = layout.split_nodes;
    benchmark::DoNotOptimize(layout.copy_parent.data());
  }
  state.counters["split_nodes"] = static_cast<double>(split);
  state.SetItemsProcessed(static_cast<int64_t>(s.x.size()) * state.iterations());
}
BENCHMARK(BM_PartitionNodes)->Unit(benchmark::kMicrosecond);

void BM_PhantomContact(benchmark::State& state) {
  Sheet s = torn_strip();
  std::vector<ParticleSet> sets{s.set()};
  SparseGrid grid(0.01);
  const Connectivity connected = [&](uint32_t, uint32_t a, uint32_t, uint32_t b) { return s.side[a] == s.side[b]; };
  grid.rebuild(sets);
  const PhantomLayout layout = partition_nodes(grid, sets, {PartitionRole{FieldKind::Shell, s.near.data()}}, connected);
  grid.set_phantom_copies(layout);
  grid.transfer_mass_momentum(sets);
  size_t pairs = 0;
  for (auto _ : state) {
    state.PauseTiming();
    grid.update_velocities(1e-4, Vec3::Zero());  // fresh trial velocities
    state.ResumeTiming();
    pairs = resolve_phantom_contact(grid, layout.copy_kind, 1e-4, 0.3).pairs_resolved;
  }
  state.counters["split_nodes"] = static_cast<double>(layout.split_nodes);
  state.counters["pairs_resolved"] = static_cast<double>(pairs);
}
BENCHMARK(BM_PhantomContact)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
