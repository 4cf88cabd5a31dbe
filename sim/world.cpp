#include "sim/world.hpp"

#include "scene/scene_error.hpp"
#include "sim/pin_system.hpp"

namespace shellfrac::sim {

namespace {

shell::ShellMaterial shell_material(const scene::model::Shell& s, const scene::model::GridSettings& grid) {
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
  m.fracture = s.material.fracture;  // its shell::FractureParams part
  if (grid.adaptive_shell(s)) m.shear_mass_share = scene::model::kAdaptiveShearMassShare;
  return m;
}

// Every mass-carrying particle of the shell starts with the shell's initial velocity: control points
// and Type III particles. With a per-control-point field, a shear particle takes the field's NURBS
// interpolation at its parameter.
void set_initial_velocity(shell::ShellPatch& patch, const scene::model::Shell& s) {
  for (auto& v : patch.v) v = s.initial_velocity;
  for (auto& v : patch.shear.v) v = s.initial_velocity;
  if (s.initial_velocity_field.empty()) return;
  for (size_t k = 0; k < patch.v.size(); ++k) patch.v[k] += s.initial_velocity_field[k];
  nurbs::SurfaceBasis basis;
  for (size_t c = 0; c < patch.shear.v.size(); ++c) {
    const Eigen::Vector2d& uv = patch.shear_parameter(c);
    patch.reference().rational_basis(uv.x(), uv.y(), basis);
    for (int k = 0; k < basis.count; ++k)
      patch.shear.v[c] += basis.R[static_cast<size_t>(k)] * s.initial_velocity_field[static_cast<size_t>(basis.index[static_cast<size_t>(k)])];
  }
}

// A solid body's particles, sampled once in its volume.
mpm::SolidParticles sample_solid(const scene::model::SolidBody& b, const std::string& source) {
  mpm::SolidParticles solid;
  const scene::model::Material& m = b.material;
  solid.material = {m.mu(), m.lambda(), m.density};
  solid.add(b.poisson_disk ? mpm::sample_poisson_disk(*b.geometry, b.lo, b.hi, b.spacing, b.seed)
                           : mpm::sample_jittered(*b.geometry, b.lo, b.hi, b.spacing, b.seed),
            b.spacing, b.initial_velocity);
  if (solid.size() == 0) throw scene::SceneError(source, "/solids", "solid \"" + b.name + "\" received no particles");
  return solid;
}

// The control points as the grid sees them (Type II: mass, momentum, generalized force). `mass` is the
// transfer mass (zero for kinematic points); empty `affine` or `flip_part`: the shell has none.
mpm::ParticleSet control_particles(shell::ShellPatch& p, std::vector<double>& mass, std::vector<Eigen::Matrix3d>& affine,
                                   std::vector<Eigen::Vector3d>& flip_part, double flip) {
  mpm::ParticleSet control;
  control.count = p.x.size();
  control.position = p.x.data();
  control.velocity = p.v.data();
  control.mass = mass.data();
  control.force = p.force.data();
  control.affine = affine.empty() ? nullptr : affine.data();
  control.flip_part = flip_part.empty() ? nullptr : flip_part.data();
  control.flip = flip;
  return control;
}

// The shear particles as the grid sees them (Type III: grid stress term, and the velocity gradient that
// advects their director); their affine velocity keeps its rotation only.
mpm::ParticleSet shear_particles(shell::ShellPatch& p, std::vector<Eigen::Matrix3d>& affine, double flip) {
  mpm::ParticleSet shear;
  shear.count = p.shear.x.size();
  shear.position = p.shear.x.data();
  shear.velocity = p.shear.v.data();
  shear.mass = p.shear.mass.data();
  shear.stress = p.shear.stress.data();
  shear.velocity_gradient = p.shear.velocity_gradient.data();
  shear.affine = affine.empty() ? nullptr : affine.data();
  shear.rigid_affine = true;
  shear.flip = flip;
  return shear;
}

}  // namespace

World::World(const scene::Model& model) {
  patches_.reserve(model.shells.size());
  for (size_t i = 0; i < model.shells.size(); ++i) {
    const scene::model::Shell& s = model.shells[i];
    try {
      patches_.emplace_back(s.surface, shell_material(s, model.grid), s.quadrature);
    } catch (const std::invalid_argument& e) {  // e.g. a degenerate (collapsed) control net
      throw scene::SceneError(model.source, "/shells/" + std::to_string(i) + "/patch", e.what());
    }
    set_initial_velocity(patches_.back(), s);
    initial_positions_.push_back(patches_.back().x);
    transfer_mass_.push_back(patches_.back().mass);
    // A shell that grid.cracking_shells "pic" puts on PIC under the adaptive transfer has no affine
    // velocity and no FLIP part.
    const bool pic_shell = model.grid.adaptive && !model.grid.adaptive_shell(s);
    affine_.emplace_back(model.grid.apic && !pic_shell ? patches_.back().x.size() : 0, Eigen::Matrix3d::Zero());
    shear_affine_.emplace_back(model.grid.apic && !pic_shell ? patches_.back().shear.x.size() : 0, Eigen::Matrix3d::Zero());
    const bool flip = model.grid.adaptive ? !pic_shell : model.grid.flip > 0;
    flip_part_.emplace_back(flip ? patches_.back().x.size() : 0, Eigen::Vector3d::Zero());
    shell_names_.push_back(s.name);
  }
  solids_.reserve(model.solids.size());
  for (const scene::model::SolidBody& b : model.solids) {
    solids_.push_back(sample_solid(b, model.source));
    solid_names_.push_back(b.name);
  }
  // Pinned control points are driven kinematically: they take no part in the grid transfers (their
  // elastic force is the support reaction, not a load on their free neighbours), and act on the rest of
  // the shell through the elastic forces alone.
  // Points held in only some directions (rollers, symmetry planes) keep their mass (sim/pin_system.hpp).
  kinematic_ = kinematic_points(model);
  for (size_t i = 0; i < kinematic_.size(); ++i)
    for (size_t k = 0; k < kinematic_[i].size(); ++k)
      if (kinematic_[i][k]) transfer_mass_[i][k] = 0.0;

  // The grid's particle sets: per patch its control points and its shear particles, then the solids.
  for (size_t i = 0; i < patches_.size(); ++i) {
    control_set_.push_back(sets_.size());
    layout_.push_back({SetKind::ControlPoints, i});
    sets_.push_back(control_particles(patches_[i], transfer_mass_[i], affine_[i], flip_part_[i], model.grid.flip));
    shear_set_.push_back(sets_.size());
    layout_.push_back({SetKind::ShearParticles, i});
    sets_.push_back(shear_particles(patches_[i], shear_affine_[i], model.grid.flip));
  }
  for (size_t k = 0; k < solids_.size(); ++k) {
    layout_.push_back({SetKind::SolidParticles, k});
    sets_.push_back(solids_[k].view());
    sets_.back().flip = model.grid.flip;  // one share for all sets keeps momentum exact (sparse_grid.cpp)
  }
}

void World::refresh_control_mass(size_t i) {
  shell::ShellPatch& p = patches_[i];
  std::vector<double>& m = transfer_mass_[i];
  const std::vector<double>& added = p.added_mass();
  // The velocity is kept, not the momentum: the added mass is a numerical inertia that moves with its
  // point, and a moving sheet must not be jolted where a crack changes its bases.
  for (size_t k = 0; k < m.size(); ++k)
    if (k >= kinematic_[i].size() || !kinematic_[i][k]) m[k] = p.mass[k] + added[k];
}

std::string World::describe_particle(size_t s, size_t k) const {
  const SetRef& r = layout_[s];
  switch (r.kind) {
    case SetKind::ControlPoints: return "control point " + std::to_string(k) + " of shell \"" + shell_names_[r.body] + "\"";
    case SetKind::ShearParticles: return "shear particle " + std::to_string(k) + " of shell \"" + shell_names_[r.body] + "\"";
    case SetKind::SolidParticles: return "particle " + std::to_string(k) + " of solid \"" + solid_names_[r.body] + "\"";
  }
  return "particle " + std::to_string(k);
}

size_t World::num_control_points() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.num_control_points();
  return n;
}

size_t World::num_shear_particles() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.shear.x.size();
  return n;
}

size_t World::num_solid_particles() const {
  size_t n = 0;
  for (const auto& s : solids_) n += s.size();
  return n;
}

size_t World::num_quadrature_points() const {
  size_t n = 0;
  for (const auto& p : patches_) n += p.num_quadrature_points();
  return n;
}

double World::kinetic_energy() const {
  double e = 0;
  for (const auto& p : patches_) {
    for (size_t k = 0; k < p.v.size(); ++k) e += 0.5 * (p.mass[k] + p.added_mass()[k]) * p.v[k].squaredNorm();
    for (size_t k = 0; k < p.shear.v.size(); ++k) e += 0.5 * p.shear.mass[k] * p.shear.v[k].squaredNorm();
  }
  for (const auto& s : solids_)
    for (size_t k = 0; k < s.size(); ++k) e += 0.5 * s.mass[k] * s.v[k].squaredNorm();
  return e;
}

namespace {

// The velocity control point k of a patch is advected with: v minus its FLIP part (none for PIC/APIC).
Eigen::Vector3d advected_velocity(const shell::ShellPatch& p, const std::vector<Eigen::Vector3d>& flip, size_t k) {
  return flip.empty() ? p.v[k] : Eigen::Vector3d(p.v[k] - flip[k]);
}

}  // namespace

double World::advected_kinetic_energy() const {
  double e = 0;
  for (size_t i = 0; i < patches_.size(); ++i) {
    const auto& p = patches_[i];
    for (size_t k = 0; k < p.v.size(); ++k)
      e += 0.5 * (p.mass[k] + p.added_mass()[k]) * advected_velocity(p, flip_part_[i], k).squaredNorm();
  }
  for (const auto& s : solids_)
    for (size_t k = 0; k < s.size(); ++k) e += 0.5 * s.mass[k] * s.v[k].squaredNorm();
  return e;
}

double World::max_advected_control_point_speed() const {
  double vmax = 0;
  for (size_t i = 0; i < patches_.size(); ++i)
    for (size_t k = 0; k < patches_[i].v.size(); ++k)
      vmax = std::max(vmax, advected_velocity(patches_[i], flip_part_[i], k).norm());
  return vmax;
}

Eigen::Vector3d World::linear_momentum() const {
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

}  // namespace shellfrac::sim
