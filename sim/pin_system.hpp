#pragma once
// The pins of a running scene (scene key "pins"): Dirichlet conditions on control points.
//
// A point held in all three components is driven kinematically, as before: it carries no mass in the grid
// transfers, its position follows the pin's motion and its elastic force is the support reaction. A point
// held in some directions only (rollers, diaphragms, symmetry planes) keeps its mass; with P the projector
// onto its held directions,
//   forces:     P f is removed before the transfer (the constraint carries it), so that at rest the free
//               components balance exactly as in a Galerkin solution with those degrees of freedom fixed;
//   velocities: after the grid-to-particle transfer P (v - v_pin) is removed;
//   positions:  after advection P (x - x_pin) is removed (round-off drift).
// The support reaction of a pin is what it adds to the shell's momentum per unit time: -P f minus the
// removed momentum per step, m P (v - v_pin) / dt. With the free-body momentum this obeys
// dP/dt = applied loads + reactions.
// A symmetry pin also ties each held point a to its neighbour b one row inwards: their velocity
// components in the symmetry plane (projector T = I - n n^T) are replaced by the mass-weighted mean, and
// their forces' T-parts are shared in proportion to mass, so the slope across the plane stays zero and no
// momentum is lost.
#include <Eigen/Core>
#include <vector>

#include "scene/model.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

// Per shell and control point, true where pins hold all three components (World: zero transfer mass).
std::vector<std::vector<bool>> kinematic_points(const scene::Model& model);

class PinSystem {
 public:
  PinSystem(const scene::Model& model, const World& world);

  // Start velocities: held components set to the pins' (the run starts consistent with its pins).
  void hold_initial_velocities(World& world) const;
  // Force stage: records each pin's reaction to the forces and removes the held components.
  void hold_forces(World& world);
  // After the grid-to-particle transfer, before advection: removes the held velocity components (their
  // momentum change joins the reactions) and averages the symmetry ties.
  void hold_velocities(World& world, double dt, double t);
  // After advection: kinematic points to the pins' poses, held components of the others to theirs.
  void hold_positions(World& world, double t) const;

  size_t num_pins() const { return reaction_.size(); }
  // Support reaction of pin i over the last step [N]. A point several pins hold splits its reaction
  // between them in scene order, each taking the part along its own directions of what is left.
  const Eigen::Vector3d& reaction(size_t pin) const { return reaction_[pin]; }

 private:
  struct Held {
    size_t shell = 0;
    size_t point = 0;
    Eigen::Matrix3d projector = Eigen::Matrix3d::Identity();  // onto the held directions
    bool kinematic = false;                                     // all three components
    size_t pin = 0;                                             // whose motion it follows
    // Every pin holding the point with its own projector: the reaction is split between them in scene
    // order, each taking the part in its directions of what the earlier ones left.
    std::vector<std::pair<size_t, Eigen::Matrix3d>> shares;
  };
  struct Tie {
    size_t shell = 0;
    size_t a = 0, b = 0;
    Eigen::Matrix3d in_plane = Eigen::Matrix3d::Identity();  // T = I - n n^T
    size_t pin = 0;
  };
  void add_reaction(const Held& h, Eigen::Vector3d r);

  const scene::Model& model_;
  std::vector<Held> held_;
  std::vector<Tie> ties_;
  std::vector<Eigen::Vector3d> reaction_;
  // Alternating sweeps of holds and ties: 1 when no point is in two ties, else kCornerSweeps.
  static constexpr int kCornerSweeps = 12;
  int sweeps_ = 1;
};

}  // namespace shellfrac::sim
