#pragma once
// The external loads of a running scene (scene key "loads"), as generalized control-point forces
// f_k = integral of R_k t dA (the external part of thesis Eq. 4.8), added in the force stage before the
// pins take their share:
//   pressure  t = p a_1 x a_2 per unit parameter area: a follower load on the deformed surface, integrated
//             with Gauss points on every knot span (the shell's in-plane rule);
//   point     f_k = R_k(u, v) F, the force spread through the basis at its parameter point;
//   edge      t = q per unit reference length, Gauss points along the edge's spans;
//   body      f_k = a (m_k + sum_c R_k(c) m_c): the acceleration of the particles' lumped masses (the
//             control point's own and its share of the Type III particles'), so the total is exactly
//             M a of the shell's particles.
// Each is scaled by its ramp at the start of the step. Loads use the NURBS basis of the uncut patch (on a
// cracked patch a load near the crack is spread over both sides).
#include <Eigen/Core>
#include <vector>

#include "scene/model.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

class LoadSystem {
 public:
  LoadSystem(const scene::Model& model, const World& world);

  bool empty() const { return loads_.empty(); }
  // Adds every load at time t to the control-point forces of its shell.
  void apply(World& world, double t);
  // The total force load i applied in the last apply() [N].
  const Eigen::Vector3d& applied(size_t i) const { return applied_[i]; }

 private:
  // A point of a load's integration rule: its basis and weight.
  struct Sample {
    std::vector<int> index;
    std::vector<double> R, Ru, Rv;
    double weight = 0;
  };
  struct Active {
    const scene::model::Load* load;
    std::vector<Sample> samples;  // pressure, point, edge
    std::vector<double> mass;     // body: per control point
  };
  std::vector<Active> loads_;
  std::vector<Eigen::Vector3d> applied_;
};

}  // namespace shellfrac::sim
