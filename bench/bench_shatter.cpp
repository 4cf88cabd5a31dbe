// The shatter loop (thesis secs. 3.2, 3.6, Table 3.3): four 10 cm shapes (box, sphere, cylinder, torus)
// of about 1,000 particles each dropped spinning onto the ground, run for one second of rigid-body time
// at 1 ms steps. Reported per run: fracture events, fragments, rigid and MPM steps, and the seconds of
// each stage (rigid bodies, MPM, crack extraction, cutting, spawning), the columns of Table 3.3.
#include <benchmark/benchmark.h>

#include "brittle/primitives.hpp"
#include "shatter/shatter_loop.hpp"

namespace {

using namespace shellfrac;
using brittle::Vec3;

shatter::BreakableSpec shape(const std::string& name, brittle::TriMesh mesh, const Vec3& spin) {
  shatter::BreakableSpec s;
  s.name = name;
  mesh.name = name;
  s.mesh = mesh;
  brittle::BrittleMaterial m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = 0.25;
  m.density = 1000;
  m.failure_stress = 3e5;
  m.fracture_energy = 10;
  s.solver.dx = 0.01;
  auto solid = std::make_shared<brittle::BrittleSolid>(
      brittle::make_solid(s.mesh, m, 0.01, brittle::Sampling::Regular, 1, name));
  solid->set_strength({}, {}, s.solver.dx);
  s.particles = solid;
  s.event.crack.grid.spacing = 0.01;
  s.impulse_threshold = 1.0;
  s.velocity = Vec3(0, 0, -2);
  s.angular_velocity = spin;
  return s;
}

void BM_ShatterFourShapes(benchmark::State& state) {
  shatter::ShatterTotals totals;
  size_t fragments = 0;
  for (auto _ : state) {
    shatter::ShatterOptions o;
    o.dt = 1e-3;
    o.ground = shatter::GroundSpec{};
    shatter::ShatterLoop loop(o);
    loop.add_breakable(shape("box", brittle::box_mesh(Vec3(-0.3, 0, 1.3), Vec3::Constant(0.05), 1), Vec3(3, -5, 7)));
    loop.add_breakable(shape("sphere", brittle::sphere_mesh(Vec3(-0.1, 0, 1.3), 0.06), Vec3(-4, 2, 1)));
    loop.add_breakable(shape("cylinder", brittle::cylinder_mesh(Vec3(0.1, 0, 1.3), 0.05, 0.12), Vec3(6, 1, -2)));
    loop.add_breakable(shape("torus", brittle::torus_mesh(Vec3(0.35, 0, 1.3), 0.06, 0.025), Vec3(2, 5, 0)));
    loop.advance_to(1.0);
    totals = loop.totals();
    fragments = 0;
    for (size_t i = 0; i < loop.pieces().size(); ++i) fragments += loop.alive(i);
  }
  state.counters["events"] = static_cast<double>(totals.events);
  state.counters["broken"] = static_cast<double>(totals.broken);
  state.counters["pieces"] = static_cast<double>(fragments);
  state.counters["rb_steps"] = static_cast<double>(totals.rigid_steps);
  state.counters["mpm_steps"] = static_cast<double>(totals.mpm_steps);
  state.counters["s_rigid"] = totals.seconds_rigid;
  state.counters["s_mpm"] = totals.seconds_mpm;
  state.counters["s_extract"] = totals.seconds_extract;
  state.counters["s_cut"] = totals.seconds_cut;
  state.counters["s_spawn"] = totals.seconds_spawn;
}
BENCHMARK(BM_ShatterFourShapes)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
