#include "tools/bench_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shellfrac::tools::bench_scenes {

namespace {

scene::Material material(double E, double nu, double density) {
  scene::Material m;
  m.youngs_modulus = E;
  m.poisson_ratio = nu;
  m.density = density;
  return m;
}

scene::Shell flat_shell(const std::string& name, scene::Vec2 size, scene::Int2 cells, double thickness,
                        const scene::Material& m) {
  scene::Shell s;
  s.name = name;
  s.patch = scene::Patch::flat(size, cells);
  s.thickness = thickness;
  s.material = m;
  return s;
}

scene::Pin pin_region(const std::string& shell, std::optional<scene::Vec2> u, std::optional<scene::Vec2> v) {
  scene::Pin p;
  p.shell = shell;
  p.region = scene::PinRegion{u, v};
  return p;
}

scene::Scene named(const std::string& name, scene::Vec3 gravity) {
  scene::Scene s;
  s.name = name;
  s.source = name + ".json";
  s.gravity = gravity;
  return s;
}

}  // namespace

void apply(scene::Scene& scene, const Discretisation& d) {
  for (scene::Shell& shell : scene.shells) shell.quadrature = {d.points, d.layers};
  scene.time.cfl = d.cfl;
  scene.grid.transfer = d.apic ? "apic" : "pic";
}

scene::Scene hanging_strip(const Discretisation& d) {
  scene::Scene s = named("bench-membrane", {0, -9.81, 0});
  s.damping = 140;  // about twice the lowest axial frequency (pi c / 2L = 70 rad/s): near critical
  scene::Shell strip = flat_shell("strip", {0.25, kStripLength}, {std::max(1, d.cells / 2), d.cells}, 0.001,
                                  material(kStripE, 0.0, kStripDensity));
  strip.patch->origin = scene::Vec3{0, kStripLength, 0};
  strip.patch->axis_u = scene::Vec3{1, 0, 0};
  strip.patch->axis_v = scene::Vec3{0, -1, 0};
  s.shells.push_back(strip);
  s.pins.push_back(pin_region("strip", std::nullopt, scene::Vec2{0.0, 0.001}));
  apply(s, d);
  return s;
}

scene::Scene cantilever(const Discretisation& d) {
  scene::Scene s = named("bench-cantilever", {0, 0, -9.81});
  s.damping = 180;
  s.shells.push_back(flat_shell("plate", {0.5, 0.1}, {d.cells, std::max(1, d.cells / 5)}, 0.05, material(2e8, 0.0, 1000)));
  // Normalised Greville abscissae: 0, 0.5/N, 1.5/N, ...: the box holds the first two columns.
  s.pins.push_back(pin_region("plate", scene::Vec2{0.0, 0.75 / d.cells}, std::nullopt));
  apply(s, d);
  return s;
}

scene::Scene mode_one_tear(const Discretisation& d) {
  const double failure_stress = 2e4, E = 5e5;
  // Linear softening needs G_f > sigma_f^2 sqrt(3) dx / (2 E); keep 60 J/m^2 (the test's value) where
  // the grid allows it.
  const double minimum = failure_stress * failure_stress * std::sqrt(3.0) / d.cells / (2 * E);
  scene::Scene s = named("bench-tear", {0, 0, 0});
  s.damping = 4.0;
  scene::Material m = material(E, 0.3, 500);
  scene::Fracture f;
  f.failure_stress = failure_stress;
  f.fracture_energy = std::max(60.0, 1.2 * minimum);
  f.regions.push_back({std::vector<scene::Vec2>{{0, 0}, {1, 0}, {1, 0.12}, {0, 0.12}}, 1e7, std::nullopt});
  f.regions.push_back({std::vector<scene::Vec2>{{0, 0.88}, {1, 0.88}, {1, 1}, {0, 1}}, 1e7, std::nullopt});
  m.fracture = f;
  scene::Shell sheet = flat_shell("sheet", {1.0, 1.0}, {d.cells, d.cells}, 0.002, m);
  sheet.cuts.push_back({std::vector<scene::Vec2>{{0.0, 0.5}, {0.2, 0.5}}, std::nullopt});
  s.shells.push_back(sheet);
  s.pins.push_back(pin_region("sheet", std::nullopt, scene::Vec2{0.0, 0.02}));
  scene::Pin pull = pin_region("sheet", std::nullopt, scene::Vec2{0.98, 1.0});
  scene::Motion motion;
  motion.keyframes = std::vector<scene::Keyframe>{{0.0, scene::Vec3{0, 0, 0}, std::nullopt},
                                                  {0.6, scene::Vec3{0, 0.15, 0}, std::nullopt}};
  pull.motion = motion;
  s.pins.push_back(pull);
  apply(s, d);
  return s;
}

scene::Scene drape(const Discretisation& d, bool two_patches) {
  auto cloth = [](const std::string& name, double width, int cells_u, int cells_v, double x0) {
    scene::Shell c = flat_shell(name, {width, 1.0}, {cells_u, cells_v}, 0.001, material(1e5, 0.3, 300));
    c.patch->origin = scene::Vec3{x0, 0.3, 0.5};
    c.patch->axis_u = scene::Vec3{1, 0, 0};
    c.patch->axis_v = scene::Vec3{0, 0, -1};
    return c;
  };
  const int n = d.cells;
  scene::Scene s = named(two_patches ? "bench-drape-two" : "bench-drape-one", {0, -9.81, 0});
  scene::Collider ball;
  ball.shape = "sphere";
  ball.center = scene::Vec3{0, 0, 0};
  ball.radius = 0.25;
  s.colliders.push_back(ball);
  if (two_patches) {
    s.shells = {cloth("left", 0.5, std::max(1, n / 2), n, -0.5), cloth("right", 0.5, n, 2 * n, 0.0)};
    scene::Interface seam;
    seam.a = scene::Edge{std::string("left"), std::string("u1")};
    seam.b = scene::Edge{std::string("right"), std::string("u0")};
    seam.continuity = "C1";
    s.interfaces.push_back(seam);
  } else {
    s.shells = {cloth("cloth", 1.0, 2 * n, 2 * n, -0.5)};
  }
  // The finer spacing sets the grid in both versions, so they differ only in the patch layout.
  s.grid.dx = 0.5 / n;
  apply(s, d);
  return s;
}

namespace {

scene::SolidRegion box_region(scene::Vec3 center, scene::Vec3 half_extents) {
  scene::SolidRegion r;
  r.shape = "box";
  r.center = center;
  r.half_extents = half_extents;
  return r;
}

scene::Collider box_collider(const LoadingBox& box) {
  scene::Collider c;
  c.name = box.name;
  c.shape = "box";
  c.center = box.center;
  c.half_extents = box.half_extents;
  c.boundary = box.boundary;
  if (box.velocity != scene::Vec3{0, 0, 0}) {
    scene::Motion m;
    m.linear_velocity = box.velocity;
    c.motion = m;
  }
  return c;
}

// A regularly sampled brittle specimen broken by `damage_model` on a 5 mm grid, two velocity fields, run
// to its end.
scene::Solid specimen_solid(const std::string& name, const NotchedSpecimen& sp, const std::string& damage_model) {
  scene::Solid b;
  b.name = name;
  b.shape = "box";
  b.center = scene::Vec3{0, sp.half_extents[1], sp.half_extents[2]};
  b.half_extents = sp.half_extents;
  b.spacing = 0.0025;
  b.sampling = "regular";
  b.remove.push_back(box_region({0, sp.half_extents[1], 0.5 * sp.notch_depth},
                                {sp.notch_half_width, 2 * sp.half_extents[1], 0.5 * sp.notch_depth}));
  scene::SolidMaterial m;
  m.youngs_modulus = kSpecimenE;
  m.poisson_ratio = kSpecimenNu;
  m.density = kSpecimenDensity;
  m.damage_model = damage_model;
  if (damage_model == "nacc") {
    scene::NaccMaterial n;
    n.alpha0 = -0.02;
    n.beta = 0.5;
    n.xi = 1.0;
    n.friction = 1.0;
    m.nacc = n;
  } else {
    m.fracture_energy = kSpecimenFractureEnergy;
  }
  if (damage_model == "phase_field") {
    scene::PhaseFieldMaterial pf;
    pf.mobility = 2000;
    m.phase_field = pf;
  } else if (damage_model == "rankine") {
    m.failure_stress = sp.failure_stress;
  }
  b.material = m;
  scene::SolidFracture f;
  f.grid_spacing = 0.005;
  f.crack_grid_spacing = 0.005;
  f.two_fields = true;
  f.crack_interval = 25;
  f.cutter = "exact";
  scene::FractureStop stop;
  stop.max_time = sp.end;
  f.stop = stop;
  b.fracture = f;
  return b;
}

scene::Scene specimen_scene(const std::string& name, const std::string& scene_name, const std::string& damage_model) {
  const NotchedSpecimen& sp = notched_specimen(name);
  scene::Scene s = named(scene_name, {0, 0, 0});
  s.time.end = sp.end;
  s.time.frame_rate = 1000;
  s.solids.push_back(specimen_solid(name, sp, damage_model));
  for (const LoadingBox& box : sp.loading) s.colliders.push_back(box_collider(box));
  return s;
}

}  // namespace

namespace {

// The bar pulled by grips that hold its last 5.5 mm at each end; the beam on supports 1 cm in from its
// ends, pressed by a box resting on its top face. (Positions are derived from the size: the coarse beam's
// crack start moves by half a millisecond when they move by round-off, see docs/phase-field.md.)
NotchedSpecimen make_specimen(bool bending) {
  NotchedSpecimen s;
  s.half_extents = bending ? scene::Vec3{0.1, 0.01, 0.02} : scene::Vec3{0.06, 0.01, 0.01};
  s.notch_half_width = bending ? 0.003 : 0.002;
  s.notch_depth = bending ? 0.012 : 0.008;
  s.failure_stress = bending ? 1e5 : 5e4;
  s.end = bending ? 0.012 : 0.01;
  const double hx = s.half_extents[0], y = s.half_extents[1], depth = 2 * s.half_extents[1], hz = s.half_extents[2];
  if (!bending) {
    s.loading = {{"grip_left", {-(hx - 0.005), y, hz}, {0.006, depth, depth}, "sticky", {-0.1, 0, 0}},
                 {"grip_right", {hx - 0.005, y, hz}, {0.006, depth, depth}, "sticky", {0.1, 0, 0}}};
  } else {
    s.loading = {{"support_left", {-(hx - 0.01), y, -0.005}, {0.005, depth, 0.005}, "slip", {0, 0, 0}},
                 {"support_right", {hx - 0.01, y, -0.005}, {0.005, depth, 0.005}, "slip", {0, 0, 0}},
                 {"load", {0, y, 2 * hz + 0.005}, {0.005, depth, 0.005}, "slip", {0, 0, -0.3}}};
  }
  return s;
}

}  // namespace

const NotchedSpecimen& notched_specimen(const std::string& name) {
  static const NotchedSpecimen bar = make_specimen(false), beam = make_specimen(true);
  if (name == "bar") return bar;
  if (name == "beam") return beam;
  throw std::invalid_argument("notched specimen must be \"bar\" or \"beam\", got \"" + name + "\"");
}

scene::Scene pulled_bar(const std::string& damage_model) {
  return specimen_scene("bar", "bench-pulled-bar", damage_model);
}

scene::Scene notched_beam(const std::string& damage_model) {
  scene::Scene s = specimen_scene("beam", "bench-notched-beam", damage_model);
  if (damage_model == "rankine") s.solids[0].material->damage_rule = "healing";
  s.solids[0].fracture->stop->damaged_fraction = 0.2;
  return s;
}

}  // namespace shellfrac::tools::bench_scenes
