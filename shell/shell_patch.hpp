#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "nurbs/nurbs_surface.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/kinematics.hpp"
#include "shell/quadrature.hpp"

namespace shellfrac::shell {

using Vec2 = Eigen::Vector2d;

// Material constants a shell patch needs for its forces.
struct ShellMaterial {
  double mu = 0, lambda = 0;  // Lamé parameters (thesis Eq. 2.4)
  double density = 0;         // kg / m^3
  double thickness = 0;       // tau
  TransverseModel transverse = TransverseModel::Condensed;
};

// Where a force evaluation failed: an inverted or degenerate quadrature point.
struct ForceFailure {
  bool failed = false;
  size_t quadrature_point = 0;  // in-plane point index
  int layer = 0;
  Vec2 parameter = Vec2::Zero();
  std::string reason;
};

// One NURBS patch of a Kirchhoff-Love shell, discretised as in thesis sec. 4.3:
//  - Type II particles: the control points (position, velocity, lumped mass) — the advected DOFs;
//  - Type IV particles: massless quadrature points, a stencil per cell on 1 or 3 layers, whose basis
//    derivatives (values, first and second) are computed once from their parameter coordinates and
//    reused every step.
// compute_forces() evaluates the Kirchhoff-Love generalised force on every control point
// (thesis Eq. 4.8 with the in-plane stress of sec. 4.5).
class ShellPatch {
 public:
  ShellPatch(const nurbs::NurbsSurface& reference, const ShellMaterial& material,
             const QuadratureRule& rule = QuadratureRule{});

  const nurbs::NurbsSurface& reference() const { return reference_; }
  const ShellMaterial& material() const { return material_; }
  // The deformed surface: reference knots and weights with the current control point positions.
  nurbs::NurbsSurface current_surface() const;

  size_t num_control_points() const { return x.size(); }
  size_t num_cells() const { return num_cells_; }
  size_t num_inplane_points() const { return param_.size(); }
  size_t num_quadrature_points() const { return param_.size() * layers_.xi3.size(); }
  int num_layers() const { return static_cast<int>(layers_.xi3.size()); }

  // Type II state (structure of arrays).
  std::vector<Vec3> x, v;
  std::vector<double> mass;
  std::vector<Vec3> force;  // Kirchhoff-Love force per control point, written by compute_forces

  // Overwrites `force` with -dPsi/dx for the current positions; stops at the first inverted point.
  ForceFailure compute_forces();
  // Total elastic energy Psi = sum_q V_q psi(F_q) of the current configuration.
  double elastic_energy() const;
  // Reference volume of the shell (sum of V_q), equal to thickness x area up to quadrature error.
  double reference_volume() const;

  // Parameter coordinate and basis (value per support control point) of in-plane point q; support
  // control point indices of its cell.
  const Vec2& parameter(size_t q) const { return param_[q]; }
  const int* support(size_t cell) const { return &support_[cell * support_size_]; }
  int support_size() const { return support_size_; }
  size_t cell_of(size_t q) const { return q / points_per_cell_; }

 private:
  void build_quadrature(const QuadratureRule& rule);
  void build_masses();
  void build_force_gather();

  nurbs::NurbsSurface reference_;
  ShellMaterial material_;
  LayerRule layers_;
  int support_size_ = 0;
  size_t num_cells_ = 0, points_per_cell_ = 0;
  std::vector<int> support_;        // cells x support_size control point indices
  std::vector<Vec2> param_;         // in-plane points, grouped by cell
  std::vector<double> basis_;       // in-plane points x support x {R, R1, R2, R11, R12, R22}
  std::vector<ReferenceLayer> ref_; // in-plane points x layers
  std::vector<double> volume_;      // in-plane points x layers: V_q
  // Deterministic gather of per-cell forces: control point c receives cell_force_[gather_[k]] for
  // k in gather_offsets_[c] .. gather_offsets_[c+1].
  std::vector<Vec3> cell_force_;
  std::vector<int> gather_offsets_, gather_;
};

}  // namespace shellfrac::shell
