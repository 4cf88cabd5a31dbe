#pragma once
// Scenes of the speed-accuracy sweeps and the stability map, built in code as scene::Scene values so that
// their discretisation can be varied; they go through scene::build() like any scene file.
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "tools/bench_sweep.hpp"

namespace shellfrac::tools::bench_scenes {

// The hanging strip of the membrane benchmark.
constexpr double kStripLength = 0.5, kStripE = 1e5, kStripDensity = 200;

// Sets every shell's quadrature, time.cfl and grid.transfer from d.
void apply(scene::Scene& scene, const Discretisation& d);
// A 0.25 x 0.5 m strip (nu = 0) hanging from its top edge under gravity, damped to rest; cells
// [max(1, N/2), N].
scene::Scene hanging_strip(const Discretisation& d);
// The 0.5 x 0.1 m cantilever plate of tests/sim/dynamics_test.cpp, N x max(1, N/5) cells, clamped by its
// first two control-point columns.
scene::Scene cantilever(const Discretisation& d);
// The mode-I tear of tests/sim/fracture_test.cpp at N x N cells: a notched 1 m^2 sheet pulled apart
// over 0.6 s, then relaxed. fracture_energy is raised where the grid needs it (coarse tiny runs).
scene::Scene mode_one_tear(const Discretisation& d);
// A 1 x 1 m cloth dropped on a ball, either as one 2N x 2N patch or as two C1-coupled patches that meet
// at x = 0 (N/2 x N cells left, N x 2N right, nested knots).
scene::Scene drape(const Discretisation& d, bool two_patches);

// The notched specimens of the brittle benches, as in scenes/brittle/: a box on z = 0, centred on x = 0
// and spanning y in [0, 2 half_extents.y], with a notch cut up from z = 0 at x = 0, and the boxes that
// load it. Material: E 10 MPa, nu 0.2, 1000 kg/m^3, G 8 J/m^2 (kSpecimen*). The stability map builds
// scenes of them (below), the crack-speed study its solver directly (tools/crack_speed.hpp).
constexpr double kSpecimenE = 1e7, kSpecimenNu = 0.2, kSpecimenDensity = 1000, kSpecimenFractureEnergy = 8;
struct LoadingBox {
  std::string name;
  scene::Vec3 center, half_extents;
  std::string boundary;  // "sticky" or "slip"
  scene::Vec3 velocity;
};
struct NotchedSpecimen {
  scene::Vec3 half_extents;
  double notch_half_width = 0, notch_depth = 0;
  double failure_stress = 0;  // Rankine's sigma_f
  double end = 0;             // seconds of loading
  std::vector<LoadingBox> loading;
};
// "bar" (pulled apart by two sticky grips at 0.1 m/s each) or "beam" (three-point bending: two slip
// supports, a box pressing its centre at 0.3 m/s); std::invalid_argument for another name.
const NotchedSpecimen& notched_specimen(const std::string& name);

// Brittle solids (docs/brittle.md), as in scenes/brittle/, by `damage_model`: "rankine" (thesis),
// "phase_field" or "nacc" (CD-MPM; their default parameters of the shipped scenes).
// The pulled notched bar: 12 x 2 x 2 cm (E 10 MPa, nu 0.2, 1000 kg/m^3), a notch 4 mm wide and 8 mm deep,
// particles at 2.5 mm on a 5 mm grid (3,024), pulled apart by two sticky grips at 0.1 m/s each for 10 ms.
// It breaks into two halves at the notch under all three models.
scene::Scene pulled_bar(const std::string& damage_model);
// The notched beam in three-point bending: 20 x 2 x 4 cm, notch 6 x 12 mm, on two slip supports, pressed
// at its centre by a box at 0.3 m/s for 12 ms. Rankine breaks it at the notch.
scene::Scene notched_beam(const std::string& damage_model);

}  // namespace shellfrac::tools::bench_scenes
