// A scene built in C++ through the public API, without JSON: a small sheet dropped under gravity for
// 0.1 s. Nothing touches it, so it falls as a rigid body; with n equal symplectic Euler steps the
// distance is exactly g t (t + t/n) / 2, which the program checks (exit 1 otherwise).
#include <cmath>
#include <cstdio>

#include <shellfrac/scene/build.hpp>
#include <shellfrac/sim/simulation.hpp>

int main() {
  using namespace shellfrac;
  scene::Scene s;
  s.name = "drop";
  s.source = "consumer";
  scene::Shell sheet;
  sheet.name = "sheet";
  sheet.patch = scene::Patch::flat({0.4, 0.4}, {4, 4});
  sheet.thickness = 0.001;
  scene::Material m;
  m.youngs_modulus = 1e5;
  m.poisson_ratio = 0.3;
  m.density = 200;
  sheet.material = m;
  s.shells.push_back(sheet);

  sim::Simulation simulation(s);
  const Eigen::Vector3d start = simulation.world().shell(0).current_surface().point(0.5, 0.5);
  simulation.advance_to(0.1);
  const double fell = start.y() - simulation.world().shell(0).current_surface().point(0.5, 0.5).y();
  const double t = 0.1, n = static_cast<double>(simulation.steps());
  const double expected = 0.5 * 9.81 * t * (t + t / n);
  std::printf("steps %ld, fell %.12f m, expected %.12f m, relative difference %.3g\n", simulation.steps(), fell,
              expected, std::abs(fell - expected) / expected);
  return std::abs(fell - expected) <= 1e-9 * expected ? 0 : 1;
}
