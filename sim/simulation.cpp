#include "sim/simulation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/surface_tessellation.hpp"
#include "sim/scene_error.hpp"

namespace shellfrac::sim {

namespace {

shell::ShellMaterial shell_material(const Shell& s) {
  shell::ShellMaterial m;
  m.mu = s.material.mu();
  m.lambda = s.material.lambda();
  m.density = s.material.density;
  m.thickness = s.thickness;
  m.transverse = s.material.transverse;
  m.stress_model = s.material.stress_model;
  m.shear.gamma = s.material.shear_stiffness.value_or(s.material.mu());
  m.shear.k = s.material.compression_stiffness.value_or(s.material.youngs_modulus);
  m.shear.friction = s.material.shear_friction;
  m.plasticity = s.material.plasticity;
  m.fracture.enabled = s.material.fracture.enabled;
  m.fracture.failure_stress = s.material.fracture.failure_stress;
  m.fracture.fracture_energy = s.material.fracture.fracture_energy;
  m.fracture.rule = s.material.fracture.rule;
  return m;
}

// Typical cell size of a patch: sqrt(mid-surface area / cells).
double cell_size(const shell::ShellPatch& p) {
  return std::sqrt(p.reference_volume() / p.material().thickness / static_cast<double>(p.num_cells()));
}

std::string format_seconds(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

}  // namespace

Simulation::Simulation(const Scene& scene) : scene_(scene), grid_(1.0) {
  patches_.reserve(scene.shells.size());
  for (size_t i = 0; i < scene.shells.size(); ++i) {
    const Shell& s = scene.shells[i];
    try {
      patches_.emplace_back(s.surface, shell_material(s), s.quadrature);
    } catch (const std::invalid_argument& e) {  // e.g. a degenerate (collapsed) control net
      throw SceneError(scene.source, "/shells/" + std::to_string(i) + "/patch", e.what());
    }
    // Every mass-carrying particle of the shell starts with it: control points and Type III particles.
    for (auto& v : patches_.back().v) v = s.initial_velocity;
    for (auto& v : patches_.back().shear.v) v = s.initial_velocity;
    initial_positions_.push_back(patches_.back().x);
    transfer_mass_.push_back(patches_.back().mass);
    pin_reaction_.emplace_back(Eigen::Vector3d::Zero());
    affine_.emplace_back(scene.grid.apic ? patches_.back().x.size() : 0, Eigen::Matrix3d::Zero());
  }
  double smallest_cell = 1e300;
  for (const auto& p : patches_) smallest_cell = std::min(smallest_cell, cell_size(p));
  for (const SolidBody& b : scene.solids) {
    mpm::SolidParticles solid;
    const Material& m = b.material;
    solid.material = {m.mu(), m.lambda(), m.density};
    solid.add(b.poisson_disk ? mpm::sample_poisson_disk(*b.geometry, b.lo, b.hi, b.spacing, b.seed)
                             : mpm::sample_jittered(*b.geometry, b.lo, b.hi, b.spacing, b.seed),
              b.spacing, b.initial_velocity);
    if (solid.size() == 0)
      throw SceneError(scene.source, "/solids", "solid \"" + b.name + "\" received no particles");
    solids_.push_back(std::move(solid));
    smallest_cell = std::min(smallest_cell, 2.0 * b.spacing);  // about 2 particles per cell and axis
  }
  grid_ = mpm::SparseGrid(scene.grid.dx.value_or(smallest_cell));

  // Elastic-wave bound per shell (explicit integration): membrane waves need dt < h / c, bending
  // waves dt < sqrt(3) h^2 / (c tau), with c = sqrt(E / (rho (1 - nu^2))) and h the finer of the grid
  // spacing and the cell size.
  elastic_bound_ = 1e300;
  for (size_t i = 0; i < patches_.size(); ++i) {
    const Material& m = scene.shells[i].material;
    const double c = std::sqrt(m.youngs_modulus / (m.density * (1 - m.poisson_ratio * m.poisson_ratio)));
    const double h = std::min(grid_.dx(), cell_size(patches_[i]));
    const double tau = scene.shells[i].thickness;
    elastic_bound_ = std::min({elastic_bound_, h / c, std::sqrt(3.0) * h * h / (c * tau)});
  }
  for (const SolidBody& b : scene.solids) {  // dilatational wave speed sqrt((lambda + 2 mu) / rho)
    const Material& m = b.material;
    elastic_bound_ = std::min(elastic_bound_, grid_.dx() / std::sqrt((m.lambda() + 2 * m.mu()) / m.density));
  }
  const double allowed = scene.time.cfl * elastic_bound_;
  if (scene.time.dt && *scene.time.dt > allowed && !scene.time.allow_substepping &&
      scene.time.enforce_stability_bound)
    throw SceneError(scene.source, "/time/dt",
                     "time step " + format_seconds(*scene.time.dt) + " s exceeds the stability bound " +
                         format_seconds(allowed) + " s (cfl " + format_seconds(scene.time.cfl) +
                         " x elastic wave bound " + format_seconds(elastic_bound_) +
                         " s): lower dt, or set \"allow_substepping\": true");

  // Pinned control points are driven kinematically: they take no part in the grid transfers (their
  // elastic force is the support reaction, not a load on their free neighbours), and act on the rest of
  // the shell through the elastic forces alone.
  for (const Pin& pin : scene.pins)
    for (int k : pin.control_points) transfer_mass_[pin.shell][static_cast<size_t>(k)] = 0.0;
  for (const auto& c : scene.colliders) colliders_.push_back(c.collider);
  // Per patch: the control points (Type II: mass, momentum, generalized force) and the shear
  // particles (Type III: grid stress term, and the velocity gradient that advects their director).
  for (size_t i = 0; i < patches_.size(); ++i) {
    shell::ShellPatch& p = patches_[i];
    mpm::ParticleSet control;
    control.count = p.x.size();
    control.position = p.x.data();
    control.velocity = p.v.data();
    control.mass = transfer_mass_[i].data();
    control.force = p.force.data();
    control.affine = scene.grid.apic ? affine_[i].data() : nullptr;
    sets_.push_back(control);
    mpm::ParticleSet shear;
    shear.count = p.shear.x.size();
    shear.position = p.shear.x.data();
    shear.velocity = p.shear.v.data();
    shear.mass = p.shear.mass.data();
    shear.stress = p.shear.stress.data();
    shear.velocity_gradient = p.shear.velocity_gradient.data();
    sets_.push_back(shear);
  }
  for (auto& solid : solids_) sets_.push_back(solid.view());
  start_positions_.resize(patches_.size());
  init_cracks();
  init_seams();
}

double Simulation::stable_dt() const {
  if (!scene_.time.enforce_stability_bound) return *scene_.time.dt;  // stability studies: as given
  double dt = scene_.time.cfl * elastic_bound_;
  if (scene_.time.dt) dt = std::min(dt, *scene_.time.dt);
  double vmax = 0;
  for (const auto& p : patches_)
    for (const auto& v : p.v) vmax = std::max(vmax, v.norm());
  for (const auto& s : solids_)
    for (const auto& v : s.v) vmax = std::max(vmax, v.norm());
  if (vmax > 0) dt = std::min(dt, scene_.time.cfl * grid_.dx() / vmax);
  return dt;
}

long Simulation::advance_to(double t) {
  long taken = 0;
  while (time_ < t - 1e-12 * std::max(1.0, t)) {
    const double remaining = t - time_;
    const double dt_max = stable_dt();
    const double n = std::ceil(remaining / dt_max - 1e-9);
    const double dt = n <= 1 ? remaining : remaining / n;
    step(dt);
    ++taken;
  }
  time_ = std::max(time_, t);
  return taken;
}

void Simulation::step(double dt) {
  stage_p2g();
  stage_forces();
  stage_grid_update(dt);
  stage_g2p(dt);
  time_ += dt;
  ++steps_;
  if (steps_ % scene_.cracks.extraction_interval == 0) stage_cracks();
  min_dt_ = steps_ == 1 ? dt : std::min(min_dt_, dt);
  max_dt_ = std::max(max_dt_, dt);
}

void Simulation::stage_p2g() {
  rebuild_grid();
  partition_phantom_nodes();  // timed on its own
  auto scope = timer_.time("p2g");
  grid_.transfer_mass_momentum(sets_);
}

void Simulation::rebuild_grid() {
  auto scope = timer_.time("p2g");
  try {
    grid_.rebuild(sets_);
  } catch (const mpm::GridError& e) {
    // sets_ holds, per shell, its control points then its shear particles; then the solids.
    std::ostringstream os;
    os << e.what() << " at ";
    if (e.set() < 2 * patches_.size())
      os << (e.set() % 2 == 0 ? "control point " : "shear particle ") << e.particle() << " of shell \""
         << scene_.shells[e.set() / 2].name << "\"";
    else
      os << "particle " << e.particle() << " of solid \"" << scene_.solids[e.set() - 2 * patches_.size()].name << "\"";
    os << " at step " << steps_ << " (t = " << time_ << " s); the time step may be too large for this material";
    throw NumericalError(os.str());
  }
}

void Simulation::stage_forces() {
  auto scope = timer_.time("forces");
  for (size_t i = 0; i < patches_.size(); ++i) {
    const shell::ForceFailure f = patches_[i].compute_forces();
    if (f.failed) {
      std::ostringstream os;
      os << f.reason << ", quadrature point " << f.quadrature_point << " at parameter (" << f.parameter.x() << ", "
         << f.parameter.y() << ") of shell \"" << scene_.shells[i].name << "\" at step " << steps_ << " (t = " << time_
         << " s)";
      throw NumericalError(os.str());
    }
  }
  for (size_t i = 0; i < solids_.size(); ++i) {
    const size_t bad = solids_[i].compute_stress();
    if (bad < solids_[i].size()) {
      std::ostringstream os;
      os << "inverted or non-finite deformation (det F <= 0) at particle " << bad << " of solid \""
         << scene_.solids[i].name << "\" at step " << steps_ << " (t = " << time_ << " s)";
      throw NumericalError(os.str());
    }
  }
  for (auto& r : pin_reaction_) r.setZero();
  for (const Pin& pin : scene_.pins) {
    auto& f = patches_[pin.shell].force;
    for (int k : pin.control_points) {
      pin_reaction_[pin.shell] -= f[static_cast<size_t>(k)];
      f[static_cast<size_t>(k)].setZero();
    }
  }
  grid_.transfer_forces(sets_);  // generalized control-point forces to the grid (thesis Eq. 4.8)
}

void Simulation::stage_grid_update(double dt) {
  auto scope = timer_.time("grid_update");
  grid_.update_velocities(dt, scene_.gravity);
  if (scene_.damping > 0) {
    const double keep = std::exp(-scene_.damping * dt);
    tbb::parallel_for(size_t{0}, grid_.num_nodes(), [&](size_t n) { grid_.node_velocity(n) *= keep; });
  }
  mpm::apply_colliders(grid_, colliders_, time_ + dt);
  if (!phantoms_.copy_parent.empty()) {  // fragments meeting at phantom copies (thesis sec. 4.7.2)
    const mpm::ContactStats c =
        mpm::resolve_phantom_contact(grid_, phantoms_.copy_kind, dt, scene_.cracks.contact_friction);
    crack_stats_.contact_pairs += c.pairs_resolved;
    crack_stats_.max_contact_residual = std::max(crack_stats_.max_contact_residual, c.max_residual);
  }
}

void Simulation::stage_g2p(double dt) {
  auto scope = timer_.time("g2p");
  grid_.transfer_to_particles(sets_);
  // Coupled patches keep x^n: the momentum correction transfers with this step's weights (Eq. 4.31).
  for (const InterfaceSpec& spec : scene_.interfaces) {
    start_positions_[static_cast<size_t>(spec.coupling.follower_patch)] =
        patches_[static_cast<size_t>(spec.coupling.follower_patch)].x;
    start_positions_[static_cast<size_t>(spec.coupling.leader_patch)] =
        patches_[static_cast<size_t>(spec.coupling.leader_patch)].x;
  }
  for (auto& p : patches_) {
    tbb::parallel_for(size_t{0}, p.x.size(), [&](size_t k) { p.x[k] += dt * p.v[k]; });  // thesis Eq. 4.9
    mpm::project_particles(p.x, p.v, colliders_, time_ + dt);
  }
  for (auto& solid : solids_) {
    solid.update(dt);
    mpm::project_particles(solid.x, solid.v, colliders_, time_ + dt);
  }
  apply_pins(time_ + dt);
  stage_coupling(dt);
  for (auto& p : patches_) p.update_shear_particles(dt);
  check_finite();
}

void Simulation::apply_pins(double t) {
  for (const Pin& pin : scene_.pins) {
    shell::ShellPatch& p = patches_[pin.shell];
    const Eigen::Isometry3d pose = pin.motion.pose(t);
    for (int k : pin.control_points) {
      const auto c = static_cast<size_t>(k);
      p.x[c] = pose * initial_positions_[pin.shell][c];
      p.v[c] = pin.motion.velocity_at(p.x[c], t);
      if (!affine_[pin.shell].empty()) affine_[pin.shell][c].setZero();
    }
  }
}

void Simulation::check_finite() const {
  for (size_t i = 0; i < solids_.size(); ++i)
    for (size_t k = 0; k < solids_[i].size(); ++k)
      if (!solids_[i].x[k].allFinite() || !solids_[i].v[k].allFinite())
        throw NumericalError("non-finite position or velocity (NaN/inf) at particle " + std::to_string(k) +
                             " of solid \"" + scene_.solids[i].name + "\" at step " + std::to_string(steps_));
  for (size_t i = 0; i < patches_.size(); ++i) {
    const auto& p = patches_[i];
    for (size_t k = 0; k < p.x.size(); ++k) {
      if (p.x[k].allFinite() && p.v[k].allFinite()) continue;
      const int nu = p.reference().num_u();
      std::ostringstream os;
      os << "non-finite position or velocity (NaN/inf) at control point " << k << " [" << k % static_cast<size_t>(nu)
         << ", " << k / static_cast<size_t>(nu) << "] of shell \"" << scene_.shells[i].name << "\" at step " << steps_
         << " (t = " << time_ << " s); the time step may be too large for this material";
      throw NumericalError(os.str());
    }
  }
}

size_t Simulation::num_control_points() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.num_control_points();
  return n;
}

size_t Simulation::num_shear_particles() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.shear.x.size();
  return n;
}

size_t Simulation::num_solid_particles() const {
  size_t n = 0;
  for (const auto& s : solids_) n += s.size();
  return n;
}

size_t Simulation::num_quadrature_points() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.num_quadrature_points();
  return n;
}

double Simulation::kinetic_energy() const {
  double e = 0;
  for (const auto& p : patches_) {
    for (size_t k = 0; k < p.v.size(); ++k) e += 0.5 * p.mass[k] * p.v[k].squaredNorm();
    for (size_t k = 0; k < p.shear.v.size(); ++k) e += 0.5 * p.shear.mass[k] * p.shear.v[k].squaredNorm();
  }
  for (const auto& s : solids_)
    for (size_t k = 0; k < s.size(); ++k) e += 0.5 * s.mass[k] * s.v[k].squaredNorm();
  return e;
}

Eigen::Vector3d Simulation::linear_momentum() const {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < patches_.size(); ++i) {
    const auto& p = patches_[i];
    for (size_t k = 0; k < p.v.size(); ++k) m += transfer_mass_[i][k] * p.v[k];
    for (size_t k = 0; k < p.shear.v.size(); ++k) m += p.shear.mass[k] * p.shear.v[k];
  }
  for (const auto& s : solids_)
    for (size_t k = 0; k < s.size(); ++k) m += s.mass[k] * s.v[k];
  return m;
}

std::vector<render_mesh::PolyMesh> Simulation::render_meshes() const {
  std::vector<render_mesh::PolyMesh> meshes(patches_.size());
  for (size_t i = 0; i < patches_.size(); ++i) {
    const crack2d::CrackGraph* graph = crack_graph(i);
    if (!graph || graph->empty()) {
      meshes[i] = render_mesh::tessellate(patches_[i].current_surface(), scene_.output.resolution_u,
                                          scene_.output.resolution_v, scene_.shells[i].name);
      continue;
    }
    // Cracked patch (thesis sec. 4.9, Algorithm 5): split the R x S grid along the crack, give each side
    // its own shadow vertices, and place them with MLS near the crack and NURBS elsewhere.
    const nurbs::NurbsSurface& ref = patches_[i].reference();
    const render_mesh::ParameterDomain domain{ref.knots_u().domain_begin(), ref.knots_u().domain_end(),
                                              ref.knots_v().domain_begin(), ref.knots_v().domain_end()};
    std::vector<render_mesh::CrackSegment2> segments;
    for (size_t e = 0; e < graph->num_edges(); ++e) segments.push_back({graph->segment(e).a, graph->segment(e).b});
    render_mesh::CrackedTessellationSettings settings;
    settings.resolution_u = scene_.output.resolution_u;
    settings.resolution_v = scene_.output.resolution_v;
    settings.shadow_offset = scene_.cracks.shadow_offset;
    const render_mesh::ParameterMesh mesh = render_mesh::separate_crack_vertices(
        render_mesh::split_parameter_grid(domain, segments, settings), settings.shadow_offset);
    std::vector<Eigen::Vector3d> positions(mesh.uv.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.uv.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      shell::MlsBasis work;
      for (size_t k = r.begin(); k != r.end(); ++k) positions[k] = patches_[i].position_at(mesh.uv[k], work);
    });
    meshes[i] = render_mesh::assemble_render_mesh(mesh, domain, std::move(positions), {}, scene_.shells[i].name);
  }
  // Solids as point clouds (one point primitive per particle).
  for (size_t i = 0; i < solids_.size(); ++i) {
    render_mesh::PolyMesh cloud;
    cloud.name = scene_.solids[i].name;
    cloud.positions = solids_[i].x;
    for (int k = 0; k < static_cast<int>(solids_[i].size()); ++k) cloud.add_face({k});
    meshes.push_back(std::move(cloud));
  }
  return meshes;
}

double Simulation::collider_penetration(const std::vector<render_mesh::PolyMesh>& meshes) const {
  double depth = 0;
  for (const auto& c : colliders_)
    for (const auto& m : meshes)
      for (const auto& x : m.positions) depth = std::max(depth, -c.signed_distance(x, time_));
  return depth;
}

}  // namespace shellfrac::sim
