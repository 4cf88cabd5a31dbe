#include "tools/stability_map.hpp"

#include "tools/run_limits.hpp"

#include "core/constants.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <memory>
#include <numeric>
#include <ostream>

#include "render_mesh/cracked_tessellation.hpp"
#include "tools/bench_scenes.hpp"
#include "tools/charts.hpp"
#include "output/progress.hpp"
#include "scene/build.hpp"
#include "scene/scene_error.hpp"
#include "output/frame_render.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::tools {

namespace fs = std::filesystem;

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::completed: return "completed";
    case Outcome::refused: return "refused";
    case Outcome::nan: return "NaN";
    case Outcome::energy_blowup: return "energy blow-up";
    case Outcome::penetration: return "penetration";
    case Outcome::area_loss: return "area loss";
    case Outcome::area_gain: return "area gain";
    case Outcome::glued: return "glued fragment";
    case Outcome::shattered: return "shattered";
    case Outcome::crease: return "crease";
  }
  return "?";
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Component label of every vertex (faces sharing a vertex are connected); -1 for unused vertices.
std::vector<int> vertex_components(const render_mesh::PolyMesh& m) {
  std::vector<int> parent(static_cast<size_t>(m.num_vertices()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[static_cast<size_t>(a)] != a) a = parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    return a;
  };
  std::vector<bool> used(parent.size(), false);
  for (int f = 0; f < m.num_faces(); ++f) {
    const int b = m.face_offsets[static_cast<size_t>(f)], e = m.face_offsets[static_cast<size_t>(f) + 1];
    for (int k = b; k < e; ++k) {
      used[static_cast<size_t>(m.face_vertices[static_cast<size_t>(k)])] = true;
      parent[static_cast<size_t>(find(m.face_vertices[static_cast<size_t>(k)]))] = find(m.face_vertices[static_cast<size_t>(b)]);
    }
  }
  std::vector<int> label(parent.size(), -1);
  for (size_t v = 0; v < parent.size(); ++v)
    if (used[v]) label[v] = find(static_cast<int>(v));
  return label;
}

// Smallest distance between the vertices of the two largest components (by vertex count; infinity for a
// single component). Small chips broken off along the crack may touch either piece; the question is
// whether the two halves came apart.
double fragment_separation(const render_mesh::PolyMesh& m) {
  const std::vector<int> label = vertex_components(m);
  std::vector<size_t> size(label.size(), 0);
  for (int l : label)
    if (l >= 0) ++size[static_cast<size_t>(l)];
  std::vector<int> order(label.size());
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + std::min<size_t>(2, order.size()), order.end(),
                    [&](int a, int b) { return size[static_cast<size_t>(a)] > size[static_cast<size_t>(b)]; });
  if (order.size() < 2 || size[static_cast<size_t>(order[1])] == 0) return std::numeric_limits<double>::infinity();
  std::vector<size_t> first, second;
  for (size_t v = 0; v < label.size(); ++v) {
    if (label[v] == order[0]) first.push_back(v);
    if (label[v] == order[1]) second.push_back(v);
  }
  double best = std::numeric_limits<double>::infinity();
  for (size_t a : first)
    for (size_t b : second) best = std::min(best, (m.positions[a] - m.positions[b]).squaredNorm());
  return std::sqrt(best);
}

// Largest angle between the normals of patch 0 at u = 1 and patch 1 at u = 0.
double seam_angle_degrees(const sim::Simulation& sim) {
  const auto left = sim.world().shell(0).current_surface(), right = sim.world().shell(1).current_surface();
  double worst = 0;
  for (int k = 0; k <= 100; ++k) {
    const double v = k / 100.0;
    const double c = std::clamp(left.evaluate(1.0, v).normal.dot(right.evaluate(0.0, v).normal), -1.0, 1.0);
    worst = std::max(worst, std::acos(c));
  }
  return worst * 180.0 / core::kPi;
}

void trip(StabilityResult& r, Outcome o, const std::string& quantity, double measured, double threshold) {
  r.outcome = o;
  r.tripped_by = quantity;
  r.measured = measured;
  r.threshold = threshold;
}

// Brittle solids: the fragments of their fracture events, slivers apart, against the expected count.
void classify_solids(const sim::Simulation& sim, const StabilityCase& c, StabilityResult& r) {
  r.fragments = r.slivers = 0;
  for (size_t b = 0; b < sim.brittle().size(); ++b) {
    const sim::BrittleSystem::Body& body = sim.brittle().body(b);
    if (!body.event) continue;
    // A sliver as summary.json counts it (output/brittle_output.cpp): below the solid's sliver volume.
    for (const brittle::Fragment& f : body.event->fragments.fragments)
      (f.properties.volume < body.spec->sliver_volume ? r.slivers : r.fragments) += 1;
  }
  if (r.fragments < c.expected_fragments)
    trip(r, Outcome::glued, "fragments (slivers apart)", r.fragments, c.expected_fragments);
  else if (r.fragments > c.expected_fragments)
    trip(r, Outcome::shattered, "fragments (slivers apart)", r.fragments, c.expected_fragments);
}

// Steps the case to its end, watching the kinetic energy against the reference peak (a blow-up ends the
// run) and the collider penetration at 24 frames per second; a numerical failure is the `nan` outcome.
void step_case(sim::Simulation& sim, const StabilityCase& c, double baseline_peak_kinetic, const StabilityThresholds& t,
               const RunLimits& limits, StabilityResult& r) {
  const double dx = sim.dx();
  const double initial_until = t.initial_fraction * c.end;
  double initial_peak = 0, next_frame = 1.0 / 24.0;
  const double frame = 1.0 / c.definition.time.frame_rate.value_or(24.0);
  const bool solids = !sim.brittle().empty();
  try {
    while (sim.time() < c.end - 1e-12 * std::max(1.0, c.end)) {
      check_stop(limits, "bench stability (" + c.scene + " / " + c.variant + " at t = " + std::to_string(sim.time()) + " s)");
      // Brittle solids step on their own grids and steps inside one step of the simulation: step it by
      // frames so that stop requests are heard.
      const double dt = std::min({sim.stable_dt(), c.end - sim.time(), frame});
      sim.step(dt);
      r.dt = std::max(r.dt, dt);
      const double ke = sim.kinetic_energy();
      if (!std::isfinite(ke))
        throw core::NumericalError("non-finite kinetic energy at step " + std::to_string(sim.steps()));
      if (solids) continue;  // their energy and penetration are the brittle solver's (it throws on inversion)
      r.peak_kinetic = std::max(r.peak_kinetic, ke);
      if (sim.time() <= initial_until) initial_peak = std::max(initial_peak, ke);
      // During the first part of the run only the default variant's peak is a reference; afterwards the
      // larger of it and this run's own initial peak.
      r.reference_kinetic = sim.time() <= initial_until ? baseline_peak_kinetic
                                                        : std::max(baseline_peak_kinetic, initial_peak);
      if (r.reference_kinetic > 0 && ke > t.energy_factor * r.reference_kinetic) {
        trip(r, Outcome::energy_blowup, "kinetic energy / reference peak", ke / r.reference_kinetic, t.energy_factor);
        break;
      }
      if (sim.time() >= next_frame - 1e-12) {  // collider check at the frame rate, as `run` does
        next_frame += 1.0 / 24.0;
        const double pen = output::collider_penetration(sim, output::render_meshes(sim)) / dx;
        r.penetration_cells = std::isnan(r.penetration_cells) ? pen : std::max(r.penetration_cells, pen);
      }
    }
    if (solids) sim.finish_brittle();  // the fracture events of solids still running at the end
  } catch (const core::NumericalError& e) {
    trip(r, Outcome::nan, "step of failure", static_cast<double>(sim.steps()), 0);
    r.detail = e.what();
  }
}

// Steps, the largest step and the bound of the brittle solvers (dx over the P-wave speed: their cfl 1 at
// rest), not of the frame loop that stepped the simulation.
void brittle_steps(const sim::Simulation& sim, StabilityResult& r) {
  r.steps = 0;
  r.dt = 0;
  r.bound = std::numeric_limits<double>::infinity();
  for (size_t b = 0; b < sim.brittle().size(); ++b) {
    const sim::BrittleSystem::Body& body = sim.brittle().body(b);
    r.steps += static_cast<long>(body.solver->steps());
    r.dt = std::max(r.dt, body.solver->dt());
    r.bound = std::min(r.bound, body.solver->options().dx / body.solid->material.wave_speed());
  }
}

// A shell run that completed: the last frame's penetration, area, fragments, their separation and the seam
// angle, checked against the thresholds in that order.
void classify_shells(const sim::Simulation& sim, const StabilityCase& c, const StabilityThresholds& t,
                     StabilityResult& r) {
  const double dx = sim.dx();
  const auto meshes = output::render_meshes(sim);
  const double pen = output::collider_penetration(sim, meshes) / dx;
  r.penetration_cells = std::isnan(r.penetration_cells) ? pen : std::max(r.penetration_cells, pen);
  double area = 0;
  r.fragments = 0;
  for (const auto& m : meshes) {
    area += render_mesh::surface_area(m);
    r.fragments += render_mesh::count_components(m);
  }
  r.area_ratio = c.reference_area > 0 ? area / c.reference_area : kNaN;
  if (c.expected_fragments > 1) r.separation_cells = fragment_separation(meshes[0]) / dx;
  if (c.seam) r.seam_angle_degrees = seam_angle_degrees(sim);

  if (r.penetration_cells > t.penetration_cells)
    trip(r, Outcome::penetration, "collider penetration [cells]", r.penetration_cells, t.penetration_cells);
  else if (r.area_ratio < 1 - t.area_tolerance)
    trip(r, Outcome::area_loss, "area / reference area", r.area_ratio, 1 - t.area_tolerance);
  else if (r.area_ratio > 1 + t.area_tolerance)
    trip(r, Outcome::area_gain, "area / reference area", r.area_ratio, 1 + t.area_tolerance);
  else if (c.expected_fragments > 1 && r.fragments < c.expected_fragments)
    trip(r, Outcome::glued, "render-mesh fragments", r.fragments, c.expected_fragments);
  else if (c.expected_fragments > 1 && r.fragments > c.expected_fragments)
    trip(r, Outcome::shattered, "render-mesh fragments", r.fragments, c.expected_fragments);
  else if (c.expected_fragments > 1 && r.separation_cells < t.separation_cells)
    trip(r, Outcome::glued, "fragment separation [cells]", r.separation_cells, t.separation_cells);
  else if (c.seam && r.seam_angle_degrees > t.crease_degrees)
    trip(r, Outcome::crease, "normal jump across the seam [deg]", r.seam_angle_degrees, t.crease_degrees);
}

}  // namespace

StabilityResult run_stability_case(const StabilityCase& c, double baseline_peak_kinetic, const StabilityThresholds& t,
                                   const RunLimits& limits) {
  StabilityResult r;
  r.scene = c.scene;
  r.variant = c.variant;
  r.penetration_cells = r.area_ratio = r.separation_cells = r.seam_angle_degrees = kNaN;
  const auto start = std::chrono::steady_clock::now();
  auto finish = [&] {
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  std::unique_ptr<sim::Simulation> sim;
  scene::Scene variant = c.definition;
  variant.source = c.scene + "-" + c.variant + ".json";
  if (c.dt_factor <= 1 || variant.time.enforce_stability_bound == false)  // the refused variant has no cost
    check_limits(variant, c.end, limits);
  try {
    sim = std::make_unique<sim::Simulation>(variant);
  } catch (const scene::SceneError& e) {
    trip(r, Outcome::refused, "dt / stability bound at " + e.json_path(), c.dt_factor, 1.0);
    r.detail = e.message();
    return finish();
  }
  r.bound = sim->elastic_wave_bound();
  step_case(*sim, c, baseline_peak_kinetic, t, limits, r);
  r.steps = sim->steps();
  r.simulated_seconds = sim->time();
  const bool solids = !sim->brittle().empty();
  if (solids) brittle_steps(*sim, r);
  if (r.outcome != Outcome::completed) return finish();
  if (solids)
    classify_solids(*sim, c, r);
  else
    classify_shells(*sim, c, t, r);
  return finish();
}

namespace {

// Brittle solids: the thesis's local Rankine damage (the default) against CD-MPM's phase field and NACC,
// each also where it is expected to fail (docs/benchmarks.md, "Stability map"). Tiny: the bar's default
// and its refused step only.
void add_solid_cases(bool full, std::vector<StabilityCase>& cases) {
  auto solid_case = [](const std::string& scene, const std::string& variant, scene::Scene definition) {
    StabilityCase c;
    c.scene = scene;
    c.variant = variant;
    c.end = *definition.time.end;
    c.definition = std::move(definition);
    c.expected_fragments = 2;
    c.reference_area = 0;  // no render mesh: the fragments decide
    return c;
  };
  auto material = [](StabilityCase& c) -> scene::SolidMaterial& { return *c.definition.solids[0].material; };
  const StabilityCase bar = solid_case("bar", "default", bench_scenes::pulled_bar("rankine"));
  cases.push_back(bar);
  {
    // The brittle step is cfl dx / (P-wave speed + fastest particle), cfl at most 1: the bound itself.
    StabilityCase c = bar;
    c.variant = "dt 2x bound (check on)";
    c.dt_factor = 2.0;
    c.definition.solids[0].fracture->cfl = 2.0;
    cases.push_back(c);
  }
  if (!full) return;
  {
    StabilityCase c = bar;
    c.variant = "dt 1x bound";
    c.dt_factor = 1.0;
    c.definition.solids[0].fracture->cfl = 1.0;
    cases.push_back(c);
  }
  // The phase field at its default l0 (half the 5 mm grid spacing), far below and above it, and solved
  // only every 100 steps; NACC at its default cohesion beta 0.5, without cohesion, and with a lot of it.
  const StabilityCase pf = solid_case("bar", "phase field", bench_scenes::pulled_bar("phase_field"));
  cases.push_back(pf);
  for (const auto& [name, l0] : {std::pair{"phase field l0 0.02 dx", 1e-4}, std::pair{"phase field l0 4 dx", 0.02}}) {
    StabilityCase c = pf;
    c.variant = name;
    material(c).phase_field->length_scale = l0;
    cases.push_back(c);
  }
  {
    StabilityCase c = pf;
    c.variant = "phase field every 100 steps";
    scene::PhaseFieldSolve solve;
    solve.interval = 100;
    c.definition.solids[0].fracture->phase_field = solve;
    cases.push_back(c);
  }
  const StabilityCase nacc = solid_case("bar", "NACC", bench_scenes::pulled_bar("nacc"));
  cases.push_back(nacc);
  for (const auto& [name, beta] : {std::pair{"NACC beta 0", 0.0}, std::pair{"NACC beta 2", 2.0}}) {
    StabilityCase c = nacc;
    c.variant = name;
    material(c).nacc->beta = beta;
    cases.push_back(c);
  }
  // Three-point bending: the phase field's split also degrades shear under the loading box.
  cases.push_back(solid_case("beam", "default", bench_scenes::notched_beam("rankine")));
  cases.push_back(solid_case("beam", "phase field", bench_scenes::notched_beam("phase_field")));
  cases.push_back(solid_case("beam", "NACC", bench_scenes::notched_beam("nacc")));
}

// Time-step variants relative to the elastic-wave bound (time.cfl = 1 so that dt is the factor times
// the bound); past the bound the check is switched off, and once left on to show the refusal.
void add_dt_variants(const StabilityCase& base, const RunLimits& limits, std::vector<StabilityCase>& cases) {
  check_limits(base.definition, base.end, limits);  // the bound needs the built scene
  const double bound = sim::Simulation(base.definition).elastic_wave_bound();
  for (double f : {0.5, 1.0, 2.0, 4.0}) {
    StabilityCase c = base;
    char name[48];
    std::snprintf(name, sizeof name, "dt %gx bound", f);
    c.variant = name;
    c.dt_factor = f;
    c.definition.time.cfl = 1.0;
    c.definition.time.dt = f * bound;
    if (f > 1) c.definition.time.enforce_stability_bound = false;
    cases.push_back(c);
  }
  StabilityCase refused = base;
  refused.variant = "dt 2x bound (check on)";
  refused.dt_factor = 2.0;
  refused.definition.time.cfl = 1.0;
  refused.definition.time.dt = 2.0 * bound;
  cases.push_back(refused);
}

void add_stress_variants(const StabilityCase& base, std::vector<StabilityCase>& cases) {
  for (const char* model : {"2d_f", "plane_strain"}) {
    StabilityCase c = base;
    c.variant = std::string("stress ") + model;
    for (scene::Shell& shell : c.definition.shells) shell.material->stress_model = model;
    cases.push_back(c);
  }
}

// The bench scenes fix "pic"; the adaptive transfer (the product's default, under which a shell that can
// crack turns to PIC once damaged), the same with the adaptive shares kept on cracking shells
// (cracking_shells "adaptive"), and APIC beside them.
void add_transfer_variants(const StabilityCase& base, bool can_crack, std::vector<StabilityCase>& cases) {
  for (const std::string transfer : {"adaptive", "apic"}) {
    StabilityCase c = base;
    c.variant = "transfer " + transfer;
    c.definition.grid.transfer = transfer;
    if (can_crack && transfer == "adaptive") {
      c.definition.grid.cracking_shells = std::string("adaptive");
      c.variant += ", cracking too";
    }
    cases.push_back(c);
  }
}

// Tearing: the mode-I tear (16 x 16 cells, torn through by 1.2 s); tiny: 12 x 12 cells for 0.05 s, long
// before the tear, so no fragments are expected.
void add_tear_cases(bool full, const RunLimits& limits, std::vector<StabilityCase>& cases) {
  StabilityCase tear;
  tear.scene = "tear";
  tear.variant = "default";
  tear.definition = bench_scenes::mode_one_tear(Discretisation{full ? 16 : 12, 4, 3, 0.5, false});
  tear.end = full ? 1.2 : 0.05;
  tear.expected_fragments = full ? 2 : 1;
  tear.reference_area = 1.0;
  cases.push_back(tear);
  add_stress_variants(tear, cases);
  StabilityCase c = tear;
  c.variant = "damage monotone";
  c.definition.shells[0].material->fracture->damage_rule = "monotone";
  cases.push_back(c);
  c = tear;
  c.variant = "single velocity field";
  c.definition.cracks.phantom_nodes = false;
  cases.push_back(c);
  // Selective mass scaling beside the cut: the step of the uncut sheet, or nearly, for 1 % added mass.
  c = tear;
  c.variant = "mass scaling 1%";
  c.definition.cracks.mass_scaling = 0.01;
  cases.push_back(c);
  add_transfer_variants(tear, true, cases);
  add_dt_variants(tear, limits, cases);
}

// Draping: the two-patch cloth coupled C1 on a ball (8 cells along the seam on the coarse side).
void add_drape_cases(bool full, const RunLimits& limits, std::vector<StabilityCase>& cases) {
  StabilityCase drape;
  drape.scene = "drape";
  drape.variant = "default";
  drape.definition = bench_scenes::drape(Discretisation{full ? 8 : 4, 4, 3, 0.5, false}, true);
  drape.end = full ? 0.6 : 0.4;
  drape.reference_area = 1.0;
  drape.seam = true;
  cases.push_back(drape);
  add_stress_variants(drape, cases);
  StabilityCase c = drape;
  c.variant = "uncoupled";
  c.definition.interfaces.clear();
  cases.push_back(c);
  c = drape;
  c.variant = "C1 without momentum correction";
  c.definition.interfaces[0].momentum_correction = false;
  cases.push_back(c);
  // The default seam closes exactly; the thesis's least-squares Eq. 4.29 beside it.
  c = drape;
  c.variant = "C1 least-squares closure";
  c.definition.interfaces[0].closure = std::string("least_squares");
  cases.push_back(c);
  add_transfer_variants(drape, false, cases);
  add_dt_variants(drape, limits, cases);
}

void write_stability_csv(const fs::path& path, const std::vector<StabilityResult>& results) {
  charts::CsvTable csv{{"scene", "variant", "outcome", "tripped_by", "measured", "threshold", "peak_kinetic",
                        "reference_kinetic", "penetration_cells", "area_ratio", "fragments", "slivers", "separation_cells",
                        "seam_angle_degrees", "steps", "dt", "bound", "dt_over_bound", "simulated_seconds",
                        "wall_seconds", "detail"},
                       {}};
  for (const auto& r : results)
    csv.add({r.scene, r.variant, outcome_name(r.outcome), r.tripped_by, charts::number(r.measured),
             charts::number(r.threshold), charts::number(r.peak_kinetic), charts::number(r.reference_kinetic),
             charts::number(r.penetration_cells), charts::number(r.area_ratio), std::to_string(r.fragments),
             std::to_string(r.slivers),
             charts::number(r.separation_cells), charts::number(r.seam_angle_degrees), std::to_string(r.steps),
             charts::number(r.dt), charts::number(r.bound), charts::number(r.bound > 0 ? r.dt / r.bound : kNaN),
             charts::number(r.simulated_seconds), charts::number(r.wall_seconds), r.detail});
  charts::write_csv(path, csv);
}

void print_stability_table(const std::vector<StabilityResult>& results, std::ostream& table) {
  table << std::left << std::setw(7) << "scene" << std::setw(32) << "variant" << std::setw(16) << "outcome"
        << "tripped by (measured vs threshold)\n";
  for (const auto& r : results) {
    table << std::left << std::setw(7) << r.scene << std::setw(32) << r.variant << std::setw(16)
          << outcome_name(r.outcome);
    if (r.outcome != Outcome::completed)
      table << r.tripped_by << " = " << charts::number(r.measured) << " (threshold " << charts::number(r.threshold)
            << ")";
    else if (std::isnan(r.area_ratio))  // a solid
      table << r.fragments << " fragments, " << r.slivers << " slivers";
    else
      table << "area " << charts::number(r.area_ratio) << ", penetration " << charts::number(r.penetration_cells)
            << " cells";
    table << "\n";
  }
}

unsigned outcome_colour(Outcome o) {
  switch (o) {
    case Outcome::completed: return 0x66bb6a;
    case Outcome::refused: return 0x64b5f6;
    case Outcome::nan: return 0xe53935;
    case Outcome::energy_blowup: return 0xff7043;
    case Outcome::penetration: return 0xab47bc;
    case Outcome::area_loss:
    case Outcome::area_gain: return 0xffca28;
    case Outcome::glued: return 0xa1887f;
    case Outcome::shattered: return 0x26c6da;
    case Outcome::crease: return 0xf48fb1;
  }
  return 0x66bb6a;
}

// The measured value a map cell shows after the outcome's name.
std::string outcome_value(const StabilityResult& r) {
  char value[96] = "";
  switch (r.outcome) {
    case Outcome::completed:
      if (std::isnan(r.area_ratio))  // a solid: no render mesh
        std::snprintf(value, sizeof value, " (%d pieces)", r.fragments);
      else
        std::snprintf(value, sizeof value, " (area %.3f)", r.area_ratio);
      break;
    case Outcome::refused: std::snprintf(value, sizeof value, ": dt %gx bound", r.measured); break;
    case Outcome::nan: std::snprintf(value, sizeof value, " at step %ld", r.steps); break;
    case Outcome::energy_blowup: std::snprintf(value, sizeof value, ": KE %.3gx peak", r.measured); break;
    case Outcome::penetration: std::snprintf(value, sizeof value, ": %.2f cells", r.measured); break;
    case Outcome::area_loss:
    case Outcome::area_gain: std::snprintf(value, sizeof value, ": area %.3f", r.measured); break;
    case Outcome::glued:
      if (r.tripped_by.find("fragments") != std::string::npos)
        std::snprintf(value, sizeof value, ": %d piece(s), %g expected", r.fragments, r.threshold);
      else
        std::snprintf(value, sizeof value, ": gap %.2g cells", r.measured);
      break;
    case Outcome::shattered:
      std::snprintf(value, sizeof value, ": %d pieces, %g expected", r.fragments, r.threshold);
      break;
    case Outcome::crease: std::snprintf(value, sizeof value, ": %.3g deg", r.measured); break;
  }
  return value;
}

// The map: one row per variant, one column per scene, each cell coloured by its outcome.
void draw_stability_map(const fs::path& path, bool full, const std::vector<StabilityResult>& results) {
  std::vector<std::string> rows, columns;
  for (const auto& r : results) {
    if (std::find(rows.begin(), rows.end(), r.variant) == rows.end()) rows.push_back(r.variant);
    if (std::find(columns.begin(), columns.end(), r.scene) == columns.end()) columns.push_back(r.scene);
  }
  std::vector<std::vector<charts::ColouredCell>> cells(rows.size(), std::vector<charts::ColouredCell>(columns.size()));
  for (const auto& r : results) {
    const size_t i = static_cast<size_t>(std::find(rows.begin(), rows.end(), r.variant) - rows.begin());
    const size_t j = static_cast<size_t>(std::find(columns.begin(), columns.end(), r.scene) - columns.begin());
    cells[i][j] = {std::string(outcome_name(r.outcome)) + outcome_value(r), outcome_colour(r.outcome)};
  }
  charts::coloured_table_chart(path,
                               std::string("stability map (") + (full ? "full" : "tiny") +
                                   "). Limits: KE 10x peak, penetration 0.5 cell, area 5%, gap 0.5 cell, "
                                   "crease 10 deg",
                               rows, columns, cells);
}

}  // namespace

std::vector<StabilityCase> stability_cases(bool full, const RunLimits& limits) {
  std::vector<StabilityCase> cases;
  add_tear_cases(full, limits, cases);
  add_drape_cases(full, limits, cases);
  add_solid_cases(full, cases);
  return cases;
}

std::vector<StabilityResult> run_stability_map(const StabilityConfig& config, std::ostream& table, std::ostream& log) {
  fs::create_directories(config.out_dir);
  const auto cases = stability_cases(config.full, config.limits);
  output::Progress progress(log, output::Progress::stderr_is_terminal(), static_cast<double>(cases.size()), "runs");
  std::vector<StabilityResult> results;
  double baseline_peak = 0;
  for (const auto& c : cases) {
    // The default variant of each scene comes first and sets the reference energy of its variants.
    const bool is_default = c.variant == "default";
    results.push_back(run_stability_case(c, is_default ? std::numeric_limits<double>::infinity() : baseline_peak,
                                         StabilityThresholds{}, config.limits));
    StabilityResult& r = results.back();
    if (is_default) {
      baseline_peak = r.peak_kinetic;
      r.reference_kinetic = r.peak_kinetic;
    }
    progress.update(static_cast<double>(results.size()),
                    c.scene + " / " + c.variant + ": " + outcome_name(r.outcome) + " (" +
                        charts::number(r.wall_seconds) + " s)");
  }
  progress.finish(std::to_string(results.size()) + " runs");

  write_stability_csv(config.out_dir / "stability.csv", results);
  print_stability_table(results, table);
  if (config.charts) draw_stability_map(config.out_dir / "stability-map.png", config.full, results);
  return results;
}

}  // namespace shellfrac::tools
