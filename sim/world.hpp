#pragma once
// The particles of a running scene: one shell patch per scene shell (control points = Type II, shear
// particles = Type III, quadrature points = Type IV) and one particle block per solid (Type I), plus the
// particle sets the grid transfers read, in a typed layout. The sets point into the patches' and solids'
// arrays, so a World never moves or resizes them (it cannot be copied).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mpm/particle_set.hpp"
#include "mpm/solid_particles.hpp"
#include "scene/model.hpp"
#include "shell/shell_patch.hpp"

namespace shellfrac::sim {

// What one particle set of the grid transfers holds.
enum class SetKind { ControlPoints, ShearParticles, SolidParticles };
struct SetRef {
  SetKind kind;
  size_t body;  // shell index for control points and shear particles, solid index for solid particles
};

class World {
 public:
  explicit World(const scene::Model& model);
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  size_t num_shells() const { return patches_.size(); }
  size_t num_solids() const { return solids_.size(); }
  shell::ShellPatch& shell(size_t i) { return patches_[i]; }
  const shell::ShellPatch& shell(size_t i) const { return patches_[i]; }
  mpm::SolidParticles& solid(size_t k) { return solids_[k]; }
  const mpm::SolidParticles& solid(size_t k) const { return solids_[k]; }

  // The particle sets of the grid transfers and what each one is.
  std::vector<mpm::ParticleSet>& particle_sets() { return sets_; }
  const std::vector<mpm::ParticleSet>& particle_sets() const { return sets_; }
  const SetRef& set(size_t s) const { return layout_[s]; }
  size_t control_set(size_t shell) const { return control_set_[shell]; }
  size_t shear_set(size_t shell) const { return shear_set_[shell]; }
  // Human-readable name of particle k of set s ("control point 12 of shell \"sheet\"").
  std::string describe_particle(size_t s, size_t k) const;

  // Control-point masses as the grid sees them: the lumped mass plus any added by mass scaling
  // (ShellPatch::added_mass), zero where a pin drives the point kinematically.
  const std::vector<double>& transfer_mass(size_t shell) const { return transfer_mass_[shell]; }
  // After the shell's bases (and so its added mass) changed: the new transfer masses. Velocities are
  // kept, so the momentum of the added mass appears with it (at most the budget's share).
  void refresh_control_mass(size_t shell);
  // APIC affine velocities of the control points (empty for PIC).
  std::vector<Eigen::Matrix3d>& affine(size_t shell) { return affine_[shell]; }
  // Affine velocities of the shear particles, of which they keep the rotational part (RPIC; empty for PIC).
  std::vector<Eigen::Matrix3d>& shear_affine(size_t shell) { return shear_affine_[shell]; }
  // FLIP part r_p delta_p of each control point's velocity from the last g2p (empty unless the transfer
  // has a FLIP share): control points advect with v_p minus it (Simulation::stage_g2p).
  const std::vector<Eigen::Vector3d>& flip_part(size_t shell) const { return flip_part_[shell]; }
  std::vector<Eigen::Vector3d>& flip_part(size_t shell) { return flip_part_[shell]; }
  // Control-point positions at the start of the run (the rest frame of the pins).
  const std::vector<Eigen::Vector3d>& initial_positions(size_t shell) const { return initial_positions_[shell]; }

  const std::string& shell_name(size_t i) const { return shell_names_[i]; }
  const std::string& solid_name(size_t k) const { return solid_names_[k]; }

  size_t num_control_points() const;
  size_t num_quadrature_points() const;
  size_t num_shear_particles() const;
  size_t num_solid_particles() const;
  double kinetic_energy() const;
  // Kinetic energy of the velocities that move the particles: control points by their velocity minus its
  // FLIP part (flip_part), which the grid does not see and the point is not advected with, and solid
  // particles. Shear particles are left out: they follow the control points (thesis Eq. 4.10), and
  // their velocity only carries their mass to the grid. The rest test (time.until_rest) reads it: with
  // the FLIP part and the shear particles a drape that has settled keeps 9e-5 J and 7-9 cm/s.
  double advected_kinetic_energy() const;
  // Largest speed of a control point by that velocity [m/s].
  double max_advected_control_point_speed() const;
  // Momentum of the particles the grid moves (pinned control points are driven, not free).
  Eigen::Vector3d linear_momentum() const;

 private:
  std::vector<shell::ShellPatch> patches_;
  std::vector<mpm::SolidParticles> solids_;
  std::vector<std::vector<Eigen::Vector3d>> initial_positions_;
  std::vector<std::vector<Eigen::Matrix3d>> affine_;  // APIC C_p per control point
  std::vector<std::vector<Eigen::Matrix3d>> shear_affine_;  // RPIC C_p per shear particle
  std::vector<std::vector<Eigen::Vector3d>> flip_part_;  // FLIP transfers: r_p delta_p per control point
  std::vector<std::vector<double>> transfer_mass_;    // control point mass, zero where pinned
  std::vector<std::vector<bool>> kinematic_;          // per control point: a pin drives it
  std::vector<std::string> shell_names_, solid_names_;
  std::vector<mpm::ParticleSet> sets_;
  std::vector<SetRef> layout_;
  std::vector<size_t> control_set_, shear_set_;
};

}  // namespace shellfrac::sim
