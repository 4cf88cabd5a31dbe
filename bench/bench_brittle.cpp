// Brittle path (thesis ch. 3): the MPM step with damage and two velocity fields on a 500K-particle solid,
// and crack extraction plus fragment cutting of a 100K-particle object, stage by stage.
//
// Anchors: thesis Table 3.3 runs 16K particles at 0.0913 s per step on 24 cores, about 0.18M
// particle-steps/s for the whole machine; our target is 3M particle-steps/s per core.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <sys/resource.h>

#include <chrono>

#include "brittle/crack_surface.hpp"
#include "brittle/fragments.hpp"
#include "brittle/primitives.hpp"
#include "brittle/regions.hpp"
#include "brittle/solver.hpp"

namespace {

using namespace shellfrac::brittle;

BrittleMaterial glassy() {
  BrittleMaterial m;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.2;
  m.density = 2500;
  m.failure_stress = 2e5;
  m.fracture_energy = 100;
  return m;
}

// A cube of n^3 particles on a lattice of spacing s with a fully damaged slab across its middle.
// CPU seconds of the whole process so far (all threads, user + system).
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

BrittleSolid cracked_cube(int n, double s) {
  BrittleSolid solid;
  solid.material = glassy();
  solid.spacing = s;
  std::vector<Vec3> pts;
  pts.reserve(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) pts.emplace_back(s * (i + 0.5), s * (j + 0.5), s * (k + 0.5));
  solid.add_particles(pts, s * s * s, Vec3::Zero());
  solid.set_strength({}, WeibullStrength{}, 2 * s);
  const double mid = 0.5 * n * s;
  for (size_t p = 0; p < solid.size(); ++p)
    if (std::abs(solid.rest[p].z() - mid) < s) solid.damage[p] = {1.0, 1.0, 0.0};
  return solid;
}

// range(0): threads; range(1): 0 = the transfer kernels picked at run time (AVX2 with FMA where the
// processor has them), 1 = the build's baseline instruction set.
void BM_BrittleStep500K(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(state.range(0)));
  const int n = 80;  // 512,000 particles
  const double s = 0.0025;
  BrittleSolid solid = cracked_cube(n, s);
  // The halves pulled apart and the whole stretched a little: damage is evaluated everywhere, the
  // two fields and their contact work along the crack.
  const double mid = 0.5 * n * s;
  for (size_t p = 0; p < solid.size(); ++p)
    solid.particles.v[p] = Vec3(0.05 * (solid.rest[p].x() - mid), 0, solid.rest[p].z() > mid ? 0.2 : -0.2);
  SolverOptions o;
  o.dx = 2 * s;
  o.two_fields = true;
  if (state.range(1) == 1) o.transfer_isa = SolidGrid::TransferIsa::Generic;
  BrittleSolver solver(solid, o);
  CrackExtractionOptions co;
  co.grid.spacing = o.dx;
  solver.update_crack(co);
  for (int warm = 0; warm < 3; ++warm) solver.step();
  const StageTimes before = solver.times();
  const double cpu_before = process_cpu_seconds();
  for (auto _ : state) solver.step();
  const double cpu = process_cpu_seconds() - cpu_before;
  const StageTimes& after = solver.times();
  const double steps = static_cast<double>(state.iterations());
  const double per_step = (after.total() - before.total()) / steps;
  state.SetLabel(solver.grid().transfer_isa());
  // CPU time of all threads: the load-independent measure on a shared machine, and the one the
  // per-core target is about.
  state.counters["cpu_ms_per_step"] = 1e3 * cpu / steps;
  state.counters["per_cpu_second"] = static_cast<double>(solid.size()) * steps / cpu;
  state.counters["per_cpu_second_vs_3M"] = static_cast<double>(solid.size()) * steps / cpu / 3e6;
  state.counters["particles"] = static_cast<double>(solid.size());
  state.counters["near_crack"] = static_cast<double>(solver.sides().near_count());
  state.counters["particle_steps_per_s"] = static_cast<double>(solid.size()) / per_step;
  state.counters["per_core"] = static_cast<double>(solid.size()) / per_step / static_cast<double>(state.range(0));
  state.counters["vs_thesis_machine"] = static_cast<double>(solid.size()) / per_step / 0.18e6;
  state.counters["p2g_ms"] = 1e3 * (after.p2g - before.p2g) / steps;
  state.counters["forces_ms"] = 1e3 * (after.forces - before.forces) / steps;
  state.counters["grid_ms"] = 1e3 * (after.grid_update - before.grid_update) / steps;
  state.counters["g2p_ms"] = 1e3 * (after.g2p - before.g2p) / steps;
  state.counters["damage_ms"] = 1e3 * (after.damage - before.damage) / steps;
}
BENCHMARK(BM_BrittleStep500K)->Args({1, 0})->Args({2, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// A 100K-particle sphere (radius 0.12 m, spacing 4.2 mm) with a damaged Y of three slabs through it;
// one pass of every stage per iteration.
void BM_CrackAndFragments100K(benchmark::State& state) {
  const double s = 0.0042, h = 2 * s, pi = 3.14159265358979323846;
  TriMesh sphere = sphere_mesh(Vec3::Zero(), 0.12, 96, 48);
  sphere.name = "sphere";
  BrittleSolid solid = make_solid(sphere, glassy(), s, Sampling::Regular, 1, "sphere");
  solid.set_strength({}, WeibullStrength{}, h);
  for (size_t p = 0; p < solid.size(); ++p)
    for (int k = 0; k < 3; ++k) {
      const Vec3 u(std::cos(pi / 2 + 2 * pi * k / 3), std::sin(pi / 2 + 2 * pi * k / 3), 0);
      const Vec3 q(solid.rest[p].x(), solid.rest[p].y(), 0);
      const double t = q.dot(u), d = t >= 0 ? (q - t * u).norm() : q.norm();
      if (d < s) solid.damage[p].c_his = 1.0;
    }
  CrackExtractionOptions co;
  co.grid.spacing = h;
  double t_extract = 0, t_regions = 0, t_exact = 0, t_vdb = 0;
  size_t frag_exact = 0, frag_vdb = 0;
  double loss_vdb = 0, loss_exact = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    const CrackExtraction crack = extract_crack(solid.rest, solid.damage_history(), co);
    auto t1 = std::chrono::steady_clock::now();
    const Regions regions = find_regions(crack.diagram, crack.crack_face);
    auto t2 = std::chrono::steady_clock::now();
    FragmentOptions fo;
    fo.density = 2500;
    fo.cutter = Cutter::Exact;
    const FragmentSet exact = cut_fragments(sphere, crack.diagram, regions, fo, "sphere");
    auto t3 = std::chrono::steady_clock::now();
    fo.cutter = Cutter::LevelSet;
    const FragmentSet vdb = cut_fragments(sphere, crack.diagram, regions, fo, "sphere");
    auto t4 = std::chrono::steady_clock::now();
    t_extract += std::chrono::duration<double>(t1 - t0).count();
    t_regions += std::chrono::duration<double>(t2 - t1).count();
    t_exact += std::chrono::duration<double>(t3 - t2).count();
    t_vdb += std::chrono::duration<double>(t4 - t3).count();
    frag_exact = exact.fragments.size();
    frag_vdb = vdb.fragments.size();
    loss_exact = exact.volume_change();
    loss_vdb = vdb.volume_change();
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["particles"] = static_cast<double>(solid.size());
  state.counters["extract_s"] = t_extract / it;
  state.counters["regions_s"] = t_regions / it;
  state.counters["cut_exact_s"] = t_exact / it;
  state.counters["cut_levelset_s"] = t_vdb / it;
  state.counters["fragments_exact"] = static_cast<double>(frag_exact);
  state.counters["fragments_levelset"] = static_cast<double>(frag_vdb);
  state.counters["volume_change_exact"] = loss_exact;
  state.counters["volume_change_levelset"] = loss_vdb;
}
BENCHMARK(BM_CrackAndFragments100K)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
