#include "sim/simulation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/format.hpp"
#include "scene/build.hpp"
#include "scene/scene_error.hpp"
#include "sim/fracture_setup.hpp"

namespace shellfrac::sim {

namespace {

// Typical cell size of a patch: sqrt(mid-surface area / cells).
double cell_size(const shell::ShellPatch& p) {
  return std::sqrt(p.reference_volume() / p.material().thickness / static_cast<double>(p.num_cells()));
}

// The grid spacing: the scene's, or the smallest shell cell (about two solid particles per cell and axis).
double grid_spacing(const scene::Model& model, const World& world) {
  if (model.grid.dx) return *model.grid.dx;
  double smallest = 1e300;
  for (size_t i = 0; i < world.num_shells(); ++i) smallest = std::min(smallest, cell_size(world.shell(i)));
  for (const scene::model::SolidBody& b : model.solids) smallest = std::min(smallest, 2.0 * b.spacing);
  for (const scene::model::BrittleBody& b : model.brittle_solids) smallest = std::min(smallest, b.solver.dx);
  return smallest;
}

// The world after init_fracture: the damage law's strengths need the grid spacing, and are set before the
// crack system cuts the prescribed cracks.
World& with_strengths(const scene::Model& model, World& world, double grid_dx) {
  init_fracture(model, world, grid_dx);
  return world;
}

}  // namespace

// thesis sec. 4.3.2: one explicit step.
const Simulation::Stage Simulation::kStages[] = {
    {"grid_rebuild", &Simulation::stage_grid_rebuild},        // sparse grid around the particles
    {"phantom_nodes", &Simulation::stage_phantom_nodes},      // copies of nodes a crack separates (4.7.1)
    {"p2g", &Simulation::stage_p2g},                          // mass and momentum to the grid
    {"forces", &Simulation::stage_forces},                    // Type I stress, Type IV force (Eq. 4.8), Type III
    {"grid_update", &Simulation::stage_grid_update},          // velocities, colliders, fragment contact (4.7.2)
    {"g2p", &Simulation::stage_g2p},                          // velocities back, advection (Eq. 4.9), pins
    {"coupling", &Simulation::stage_coupling},                // follower rows from leaders (4.8)
    {"shear_particles", &Simulation::stage_shear_particles},  // Type III positions (Eq. 4.10), director
    {"cracks", &Simulation::stage_cracks},                    // every k steps: crack graphs (4.4.2), bases (4.6)
    {"brittle", &Simulation::stage_brittle},                  // brittle solids to t + dt (ch. 3), fracture events
    {"rigid", &Simulation::stage_rigid},                      // shatter loop to t + dt (3.6): rigid bodies, events
};

Simulation::Simulation(const scene::Scene& scene) : Simulation(scene::build(scene)) {}

Simulation::Simulation(const scene::Model& model)
    : model_(model),
      world_(model_),
      pin_reaction_(world_.num_shells(), Eigen::Vector3d::Zero()),
      pins_(model_, world_),
      loads_(model_, world_),
      grid_(grid_spacing(model_, world_)),
      cracks_(model_, with_strengths(model_, world_, grid_.dx())),
      seams_(model_, world_),
      brittle_(model_),
      shatter_(model_) {
  // Elastic-wave bound per shell (explicit integration): membrane waves need dt < h / c, bending
  // waves dt < sqrt(3) h^2 / (c tau), with c = sqrt(E / (rho (1 - nu^2))) and h the finer of the grid
  // spacing and the cell size.
  elastic_bound_ = 1e300;
  for (size_t i = 0; i < world_.num_shells(); ++i) {
    const scene::model::Material& m = model_.shells[i].material;
    const double c = std::sqrt(m.youngs_modulus / (m.density * (1 - m.poisson_ratio * m.poisson_ratio)));
    const double h = std::min(grid_.dx(), cell_size(world_.shell(i)));
    const double tau = model_.shells[i].thickness;
    shell_wave_bounds_.emplace_back(h / c, std::sqrt(3.0) * h * h / (c * tau));
    elastic_bound_ = std::min({elastic_bound_, shell_wave_bounds_.back().first, shell_wave_bounds_.back().second});
  }
  for (const scene::model::SolidBody& b : model_.solids) {  // dilatational wave speed sqrt((lambda + 2 mu) / rho)
    const scene::model::Material& m = b.material;
    solid_wave_bound_ = std::min(solid_wave_bound_, grid_.dx() / std::sqrt((m.lambda() + 2 * m.mu()) / m.density));
  }
  elastic_bound_ = std::min(elastic_bound_, solid_wave_bound_);
  const scene::model::TimeSettings& time = model_.time;
  const double allowed = time.cfl * elastic_bound_;
  if (time.dt && *time.dt > allowed && !time.allow_substepping && time.enforce_stability_bound)
    throw scene::SceneError(model_.source, "/time/dt",
                            "time step " + core::format_number(*time.dt, 4) + " s exceeds the stability bound " +
                                core::format_number(allowed, 4) + " s (cfl " + core::format_number(time.cfl, 4) +
                                " x elastic wave bound " + core::format_number(elastic_bound_, 4) +
                                " s): lower dt, or set \"allow_substepping\": true");
  for (const auto& c : model_.colliders) colliders_.push_back(c.collider);
  pins_.hold_initial_velocities(world_);
  if (model_.grid.adaptive) shares_.attach(world_, model_);
  // Prescribed cuts may already reach a seam.
  seams_.update_cracks(world_, cracks_);
  cracks_.count_state(world_);
}

Simulation::~Simulation() = default;

Span<Eigen::Vector3d> Simulation::positions(size_t shell) {
  auto& x = world_.shell(shell).x;
  return {x.data(), x.size()};
}

Span<Eigen::Vector3d> Simulation::velocities(size_t shell) {
  auto& v = world_.shell(shell).v;
  return {v.data(), v.size()};
}

Span<Eigen::Vector3d> Simulation::shear_velocities(size_t shell) {
  auto& v = world_.shell(shell).shear.v;
  return {v.data(), v.size()};
}

double Simulation::current_elastic_wave_bound() const {
  double bound = solid_wave_bound_;
  for (size_t i = 0; i < shell_wave_bounds_.size(); ++i) {
    const shell::ShellPatch& patch = world_.shell(i);
    bound = std::min({bound, shell_wave_bounds_[i].first * patch.membrane_step_scale(),
                      shell_wave_bounds_[i].second * patch.bending_step_scale()});
  }
  return bound;
}

double Simulation::stable_dt() const {
  if (!model_.time.enforce_stability_bound) return *model_.time.dt;  // stability studies: as given
  double dt = model_.time.cfl * current_elastic_wave_bound();
  if (model_.time.dt) dt = std::min(dt, *model_.time.dt);
  double vmax = 0;
  for (size_t i = 0; i < world_.num_shells(); ++i)
    for (const auto& v : world_.shell(i).v) vmax = std::max(vmax, v.norm());
  for (size_t k = 0; k < world_.num_solids(); ++k)
    for (const auto& v : world_.solid(k).v) vmax = std::max(vmax, v.norm());
  if (vmax > 0) dt = std::min(dt, model_.time.cfl * grid_.dx() / vmax);
  return dt;
}

long Simulation::advance_to(double t, const std::function<bool()>& should_stop) {
  long taken = 0;
  while (time_ < t - 1e-12 * std::max(1.0, t)) {
    const double remaining = t - time_;
    const double dt_max = stable_dt();
    const double n = std::ceil(remaining / dt_max - 1e-9);
    const double dt = n <= 1 ? remaining : remaining / n;
    step(dt);
    ++taken;
    if (should_stop && should_stop()) return taken;
  }
  time_ = std::max(time_, t);
  return taken;
}

void Simulation::step(double dt) {
  for (const Stage& stage : kStages) {
    auto scope = timer_.time(stage.name);
    (this->*stage.run)(dt);
  }
  time_ += dt;
  ++steps_;
  min_dt_ = steps_ == 1 ? dt : std::min(min_dt_, dt);
  max_dt_ = std::max(max_dt_, dt);
}

void Simulation::stage_grid_rebuild(double) {
  try {
    grid_.rebuild(world_.particle_sets());
  } catch (const mpm::GridError& e) {
    std::ostringstream os;
    os << e.what() << " at " << world_.describe_particle(e.set(), e.particle()) << " at step " << steps_
       << " (t = " << time_ << " s); the time step may be too large for this material";
    const SetRef& where = world_.set(e.set());
    core::NumericalLocation at;
    const bool solid = where.kind == SetKind::SolidParticles;
    at.body = solid ? world_.solid_name(where.body) : world_.shell_name(where.body);
    at.body_kind = solid ? "solid" : "shell";
    at.particle_kind = solid ? "solid particle" : where.kind == SetKind::ControlPoints ? "control point" : "shear particle";
    at.particle = static_cast<long>(e.particle());
    at.step = steps_;
    at.time = time_;
    throw NumericalError(os.str(), at);
  }
}

void Simulation::stage_phantom_nodes(double) { cracks_.partition(world_, grid_, seams_); }

void Simulation::stage_p2g(double) { grid_.transfer_mass_momentum(world_.particle_sets()); }

void Simulation::stage_forces(double) {
  for (size_t i = 0; i < world_.num_shells(); ++i) {
    const shell::ForceFailure f = world_.shell(i).compute_forces();
    if (f.failed) {
      std::ostringstream os;
      os << f.reason << ", quadrature point " << f.quadrature_point << " at parameter (" << f.parameter.x() << ", "
         << f.parameter.y() << ") of shell \"" << world_.shell_name(i) << "\" at step " << steps_ << " (t = " << time_
         << " s)";
      throw NumericalError(os.str(), {world_.shell_name(i), "shell", "quadrature point",
                                      static_cast<long>(f.quadrature_point), steps_, time_});
    }
  }
  for (size_t k = 0; k < world_.num_solids(); ++k) {
    const size_t bad = world_.solid(k).compute_stress();
    if (bad < world_.solid(k).size()) {
      std::ostringstream os;
      os << "inverted or non-finite deformation (det F <= 0) at particle " << bad << " of solid \""
         << world_.solid_name(k) << "\" at step " << steps_ << " (t = " << time_ << " s)";
      throw NumericalError(os.str(), {world_.solid_name(k), "solid", "solid particle", static_cast<long>(bad), steps_, time_});
    }
  }
  if (!loads_.empty()) loads_.apply(world_, time_);  // external loads at the start of the step
  pins_.hold_forces(world_);
  grid_.transfer_forces(world_.particle_sets());  // generalized control-point forces to the grid (thesis Eq. 4.8)
}

void Simulation::stage_grid_update(double dt) {
  grid_.update_velocities(dt, model_.gravity);
  if (model_.damping > 0) {
    const double keep = std::exp(-model_.damping * dt);
    tbb::parallel_for(size_t{0}, grid_.num_nodes(), [&](size_t n) { grid_.node_velocity(n) *= keep; });
  }
  mpm::apply_colliders(grid_, colliders_, time_ + dt);
  for (size_t k = 0; k < shatter_.num_strikers(); ++k)  // projectiles of the rigid world (sec. 4.10.7)
    if (const mpm::Collider* c = shatter_.striker(k, time_ + dt))
      shatter_.add_contact(k, mpm::apply_collider(grid_, *c, 0.0, shatter_.striker_centre(k)));
  if (cracks_.has_phantoms()) {  // fragments meeting at phantom copies (thesis sec. 4.7.2)
    const mpm::ContactStats c =
        mpm::resolve_phantom_contact(grid_, cracks_.phantoms().copy_kind, dt, model_.cracks.contact_friction);
    cracks_.count_contact(c.pairs_resolved, c.max_residual);
  }
}

void Simulation::stage_g2p(double dt) {
  // FLIP keeps the particles' own share of the velocity, which the grid's damping never sees: damp that
  // share at the same rate (one factor for all sets keeps momentum exact).
  const double keep = model_.damping > 0 ? std::exp(-model_.damping * dt) : 1.0;
  if (model_.grid.adaptive) {
    // The scene's colliders at the end of the step, and the rigid world's projectiles (posed at 0, see
    // ShatterSystem::striker); a quadratic B-spline stencil reaches nodes up to 1.5 dx away along each axis.
    std::vector<TransferShares::PosedCollider> posed;
    for (const mpm::Collider& c : colliders_) posed.emplace_back(&c, time_ + dt);
    for (size_t k = 0; k < shatter_.num_strikers(); ++k)
      if (const mpm::Collider* c = shatter_.striker(k, time_ + dt)) posed.emplace_back(c, 0.0);
    shares_.update(world_, model_.grid.flip * keep, model_.grid.flip_active * keep, posed,
                   1.5 * std::sqrt(3.0) * grid_.dx());
  } else {
    for (mpm::ParticleSet& s : world_.particle_sets()) s.flip = model_.grid.flip * keep;
  }
  grid_.transfer_to_particles(world_.particle_sets(), dt);
  if (model_.grid.adaptive) shares_.drop_damaged_affine(world_);
  pins_.hold_velocities(world_, dt, time_ + dt);
  seams_.save_start_positions(world_);
  for (size_t i = 0; i < world_.num_shells(); ++i) {
    shell::ShellPatch& p = world_.shell(i);
    // thesis Eq. 4.9. Under a FLIP transfer without the FLIP part of the velocity (World::flip_part): the
    // grid's velocity plus whatever pins and seams set after g2p.
    const std::vector<Eigen::Vector3d>& flip_part = world_.flip_part(i);
    if (flip_part.empty())
      tbb::parallel_for(size_t{0}, p.x.size(), [&](size_t k) { p.x[k] += dt * p.v[k]; });
    else
      tbb::parallel_for(size_t{0}, p.x.size(), [&](size_t k) { p.x[k] += dt * (p.v[k] - flip_part[k]); });
    mpm::project_particles(p.x, p.v, colliders_, time_ + dt);
    for (size_t k = 0; k < shatter_.num_strikers(); ++k)
      if (const mpm::Collider* c = shatter_.striker(k, time_ + dt))
        shatter_.add_contact(k, mpm::project_particles(p.x, p.v, world_.transfer_mass(i).data(), *c, 0.0,
                                                       shatter_.striker_centre(k)));
  }
  for (size_t k = 0; k < world_.num_solids(); ++k) {
    mpm::SolidParticles& solid = world_.solid(k);
    solid.update(dt);
    mpm::project_particles(solid.x, solid.v, colliders_, time_ + dt);
    for (size_t j = 0; j < shatter_.num_strikers(); ++j)
      if (const mpm::Collider* c = shatter_.striker(j, time_ + dt))
        shatter_.add_contact(j, mpm::project_particles(solid.x, solid.v, solid.mass.data(), *c, 0.0, shatter_.striker_centre(j)));
  }
  pins_.hold_positions(world_, time_ + dt);
  for (auto& r : pin_reaction_) r.setZero();
  for (size_t i = 0; i < model_.pins.size(); ++i) pin_reaction_[model_.pins[i].shell] += pins_.reaction(i);
}

void Simulation::stage_coupling(double dt) {
  if (!seams_.empty()) seams_.couple(world_, grid_, dt);
}

void Simulation::stage_shear_particles(double dt) {
  for (size_t i = 0; i < world_.num_shells(); ++i) world_.shell(i).update_shear_particles(dt);
  check_finite();
}

void Simulation::stage_cracks(double) {
  // Runs after the step whose number (counted from 1) is a multiple of the extraction interval.
  if ((steps_ + 1) % model_.cracks.extraction_interval != 0 || !cracks_.any()) return;
  if (cracks_.extract(world_) && !model_.interfaces.empty()) {
    seams_.update_cracks(world_, cracks_);  // may continue a crack into a coupled neighbour
    cracks_.count_state(world_);
  }
}

void Simulation::stage_rigid(double dt) {
  shatter_.take_contacts();  // what the projectiles gave the MPM material this step, before they move on
  shatter_.advance_to(time_ + dt);
}

void Simulation::stage_brittle(double dt) {
  if (!brittle_.empty()) brittle_.advance_to(time_ + dt);
}

double Simulation::max_control_point_speed() const {
  double vmax = 0;
  for (size_t i = 0; i < world_.num_shells(); ++i)
    for (const auto& v : world_.shell(i).v) vmax = std::max(vmax, v.norm());
  return vmax;
}

void Simulation::check_finite() const {
  for (size_t k = 0; k < world_.num_solids(); ++k) {
    const mpm::SolidParticles& s = world_.solid(k);
    for (size_t j = 0; j < s.size(); ++j)
      if (!s.x[j].allFinite() || !s.v[j].allFinite())
        throw NumericalError("non-finite position or velocity (NaN/inf) at particle " + std::to_string(j) +
                             " of solid \"" + world_.solid_name(k) + "\" at step " + std::to_string(steps_),
                             {world_.solid_name(k), "solid", "solid particle", static_cast<long>(j), steps_, time_});
  }
  for (size_t i = 0; i < world_.num_shells(); ++i) {
    const auto& p = world_.shell(i);
    for (size_t k = 0; k < p.x.size(); ++k) {
      if (p.x[k].allFinite() && p.v[k].allFinite()) continue;
      const int nu = p.reference().num_u();
      std::ostringstream os;
      os << "non-finite position or velocity (NaN/inf) at control point " << k << " [" << k % static_cast<size_t>(nu)
         << ", " << k / static_cast<size_t>(nu) << "] of shell \"" << world_.shell_name(i) << "\" at step " << steps_
         << " (t = " << time_ << " s); the time step may be too large for this material";
      throw NumericalError(os.str(), {world_.shell_name(i), "shell", "control point", static_cast<long>(k), steps_, time_});
    }
  }
}

}  // namespace shellfrac::sim
