#pragma once
// A running scene: the Kirchhoff-Love shell patches and solids of a World on a sparse MPM grid (thesis sec.
// 4.3.2), advanced by explicit symplectic Euler through the named, timed stages of step():
//
//   grid_rebuild -> phantom_nodes -> p2g -> forces -> grid_update -> g2p -> coupling -> shear_particles
//   -> cracks (every k steps) -> brittle (the brittle solids, on their own grids and steps)
//
// Near cracks the phantom stage gives grid nodes one copy per fragment side and grid_update resolves
// contact between the copies (thesis sec. 4.7). Constitutive updates run where their kinematics are at
// hand: the Type IV damage and plastic return mapping inside the force pass (on the trial state), the Type
// III director update and return mapping in the shear_particles stage (after the coupling has placed the
// control points). The crack graphs live in a CrackSystem, the coupled seams in a SeamSystem; the two
// talk through explicit calls in the stages below.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "crack2d/crack_graph.hpp"
#include "mpm/colliders.hpp"
#include "mpm/sparse_grid.hpp"
#include "scene/model.hpp"
#include "scene/scene.hpp"
#include "sim/brittle_system.hpp"
#include "sim/shatter_system.hpp"
#include "sim/crack_system.hpp"
#include "sim/loads.hpp"
#include "sim/pin_system.hpp"
#include "sim/seam_system.hpp"
#include "sim/span.hpp"
#include "sim/stage_timer.hpp"
#include "sim/transfer_shares.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

using NumericalError = core::NumericalError;

class Simulation {
 public:
  // Builds the particles, grid, cracks and seams. Throws SceneError for input only the built simulation
  // can judge (a dt above the stability bound, a fracture energy below the grid's minimum).
  explicit Simulation(const scene::Model& model);
  // Builds the scene first (scene::build: validation, defaults, geometry).
  explicit Simulation(const scene::Scene& scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;  // the grid's particle views point into the world
  Simulation& operator=(const Simulation&) = delete;

  // Largest stable step: cfl times the elastic-wave bound of the stiffest shell on the grid, further
  // limited so that no particle moves more than cfl grid cells per step at the current speeds.
  double stable_dt() const;
  // The elastic-wave part of the bound (without the cfl factor) of the uncut NURBS bases, for reports.
  double elastic_wave_bound() const { return elastic_bound_; }
  // The same for the current bases: each shell's membrane and bending bounds shrink with the stiffness of
  // the MLS bases beside its cracks (ShellPatch::membrane_step_scale). What stable_dt() uses.
  double current_elastic_wave_bound() const;

  // One step of size dt through the stages. Throws NumericalError naming the particle, shell and step.
  void step(double dt);
  // Steps until time t (equal steps no larger than the allowed step), returns the steps taken. With
  // should_stop, it is asked after every step and a true answer ends the call early (time() < t then):
  // how a caller interrupts a long advance between steps (the Python module's KeyboardInterrupt).
  long advance_to(double t, const std::function<bool()>& should_stop = {});

  double time() const { return time_; }
  long steps() const { return steps_; }
  double min_dt() const { return min_dt_; }
  double max_dt() const { return max_dt_; }
  double dx() const { return grid_.dx(); }
  const StageTimer& timer() const { return timer_; }
  const scene::Model& model() const { return model_; }

  // The particles, read-only. To set up a state from code (initial velocities of chosen points, say),
  // use the spans below: their elements can be written, the arrays cannot be resized.
  const World& world() const { return world_; }
  Span<Eigen::Vector3d> positions(size_t shell);
  Span<Eigen::Vector3d> velocities(size_t shell);
  Span<Eigen::Vector3d> shear_velocities(size_t shell);

  size_t num_control_points() const { return world_.num_control_points(); }
  size_t num_quadrature_points() const { return world_.num_quadrature_points(); }
  size_t num_shear_particles() const { return world_.num_shear_particles(); }
  size_t num_solid_particles() const { return world_.num_solid_particles(); }
  // Grid nodes the particles touched at the last grid rebuild (0 before the first step), phantom copies
  // not counted.
  size_t num_grid_nodes() const { return grid_.num_grid_nodes(); }
  double kinetic_energy() const { return world_.kinetic_energy(); }
  double advected_kinetic_energy() const { return world_.advected_kinetic_energy(); }
  Eigen::Vector3d linear_momentum() const { return world_.linear_momentum(); }
  // Whether shell i, which can crack, runs PIC (RPIC, APIC) instead of the adaptive shares at this step:
  // while it is damaged (grid.cracking_shells "pic_while_damaged" or "rpic_while_damaged"; never under the
  // default "pic_where_damaged", which runs only the particles beside damage as PIC),
  // or for good since damage or a crack appeared on it ("adaptive_then_pic", "adaptive_then_apic").
  bool transfer_turned(size_t shell) const { return shares_.turned(shell); }
  // Total force the pins exert on shell i over the last step (sim/pin_system.hpp: minus the force on the
  // held components, minus the momentum the held components lost, per unit time).
  const Eigen::Vector3d& pin_reaction(size_t shell) const { return pin_reaction_[shell]; }
  // The same for scene pin i alone (a point held by several pins splits it: sim/pin_system.hpp).
  const Eigen::Vector3d& pin_set_reaction(size_t pin) const { return pins_.reaction(pin); }
  // The total force scene load i applied in the last step [N].
  const Eigen::Vector3d& applied_load(size_t load) const { return loads_.applied(load); }
  // Largest control-point speed [m/s], FLIP part included.
  double max_control_point_speed() const;
  // Largest speed a control point moves with [m/s] (time.until_rest; World::advected_kinetic_energy).
  double max_advected_control_point_speed() const { return world_.max_advected_control_point_speed(); }
  const std::vector<mpm::Collider>& colliders() const { return colliders_; }

  const CrackStats& crack_stats() const { return cracks_.stats(); }
  // Crack graph of shell i, or null when the shell cannot crack.
  const crack2d::CrackGraph* crack_graph(size_t shell) const { return cracks_.graph(shell); }
  const SeamSystem& seams() const { return seams_; }
  // The brittle solids (docs/brittle.md) and their fracture events.
  const BrittleSystem& brittle() const { return brittle_; }
  // The shatter loop of the brittle solids with "rigid_body" (docs/brittle.md); empty() without them.
  const ShatterSystem& shatter() const { return shatter_; }
  // Sees every MPM step of the shatter loop's fracture events and may abandon one (shatter::EventObserver).
  void set_event_observer(shatter::EventObserver observer) { shatter_.set_event_observer(std::move(observer)); }
  // Fracture events for the brittle solids still running (called by the run driver at the scene's end).
  void finish_brittle() { brittle_.finish_running(); }
  // True when the scene holds only brittle solids and all of them have had their fracture event.
  bool finished() const { return world_.num_shells() == 0 && world_.num_solids() == 0 && !brittle_.empty() && brittle_.done(); }
  // Follower control points of scene interface i that a crack across the seam has released.
  size_t released_seam_points(size_t i) const { return seams_.released_points(i); }
  // Seam coordinates (leader edge parameter in [0, 1]) where cracks meet the seam of interface i.
  const std::vector<double>& seam_cracks(size_t i) const { return seams_.crack_positions(i); }

 private:
  // The stages of step(), in order (thesis sec. 4.3.2).
  void stage_grid_rebuild(double dt);
  void stage_phantom_nodes(double dt);
  void stage_p2g(double dt);
  void stage_forces(double dt);
  void stage_grid_update(double dt);
  void stage_g2p(double dt);
  void stage_coupling(double dt);
  void stage_shear_particles(double dt);
  void stage_cracks(double dt);
  void stage_brittle(double dt);
  void stage_rigid(double dt);
  struct Stage {
    const char* name;
    void (Simulation::*run)(double dt);
  };
  static const Stage kStages[];

  void check_finite() const;

  scene::Model model_;
  World world_;
  std::vector<Eigen::Vector3d> pin_reaction_;  // per shell, from the last step
  PinSystem pins_;
  LoadSystem loads_;
  TransferShares shares_;  // per-particle FLIP shares of the adaptive transfer
  std::vector<mpm::Collider> colliders_;
  mpm::SparseGrid grid_;
  CrackSystem cracks_;
  SeamSystem seams_;
  BrittleSystem brittle_;
  ShatterSystem shatter_;
  StageTimer timer_;
  double elastic_bound_ = 0;
  // Per shell: the membrane (h / c) and bending (sqrt(3) h^2 / (c tau)) wave bounds of the NURBS bases.
  std::vector<std::pair<double, double>> shell_wave_bounds_;
  double solid_wave_bound_ = 1e300;
  double time_ = 0;
  long steps_ = 0;
  double min_dt_ = 0, max_dt_ = 0;
};

}  // namespace shellfrac::sim
