#pragma once
// Probes (output.probes): named parameter points of a shell, evaluated through the patch's NURBS basis
// on the current control points: position x = sum R_k x_k, displacement against the start, velocity
// v = sum R_k v_k, and the mid-surface Cauchy stress of the Kirchhoff-Love model (thesis Eq. 4.14 on the
// mid-surface layer: sigma = tau^{ab} a_a (x) a_b / (J lambda_3)), elastic against the reference surface.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "scene/model.hpp"
#include "shell/in_plane_stress.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

struct ProbeSample {
  double time = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero(), displacement = Eigen::Vector3d::Zero(),
                  velocity = Eigen::Vector3d::Zero();
  // Symmetric Cauchy stress [Pa]: xx, yy, zz, xy, yz, xz; NaN where the surface is degenerate.
  std::array<double, 6> stress{};
};

class ProbeSampler {
 public:
  ProbeSampler(const scene::Model& model, const World& world);
  size_t size() const { return probes_.size(); }
  ProbeSample sample(size_t probe, const World& world, double time) const;

 private:
  struct Point {
    size_t shell = 0;
    std::vector<int> index;
    std::vector<double> R, Ru, Rv;
    Eigen::Vector3d start = Eigen::Vector3d::Zero();
    shell::ReferenceLayer reference{};
  };
  std::vector<Point> probes_;
};

}  // namespace shellfrac::sim
