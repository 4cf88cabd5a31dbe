#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "nurbs/nurbs_surface.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/kinematics.hpp"
#include "shell/plasticity.hpp"
#include "shell/quadrature.hpp"
#include "shell/shear_model.hpp"

namespace shellfrac::shell {

using Vec2 = Eigen::Vector2d;

// Material constants a shell patch needs for its forces.
struct ShellMaterial {
  double mu = 0, lambda = 0;  // Lamé parameters (thesis Eq. 2.4)
  double density = 0;         // kg / m^3
  double thickness = 0;       // tau
  TransverseModel transverse = TransverseModel::Condensed;
  ShearParams shear;          // Type-III shearing/compression model
  PlasticityParams plasticity;  // Type-IV von Mises plasticity (metal sheets)
};

// Share of a cell's mass carried by its Type-III particle; the control points carry the rest. Type III
// particles must carry mass (thesis sec. 4.3.2: Types I-III transfer mass and momentum): their stress
// reaches grid nodes that no control point touches, and a massless node would drop that force and break
// momentum conservation.
inline constexpr double kShearParticleMassShare = 0.5;

// Type-III particles: one per cell at the parameter location of the cell's middle control point
// (thesis sec. 4.3.2). They carry the elastic director d_3 that the grid velocity advects, and resist
// compression and (under friction) shear.
struct ShearParticles {
  std::vector<Vec3> x, v;              // position (NURBS-interpolated, thesis Eq. 4.10); grid velocity
  std::vector<double> mass;            // kShearParticleMassShare of the cell's mass
  std::vector<Vec3> director;          // elastic d_3
  std::vector<Mat3> reference_inverse; // D^-1 with D = E^T [A_1 A_2 N] in the local frame E = [E_1 E_2 N]
  std::vector<Mat3> stress;            // grid stress term S_p = V dpsi/dd_3 (x) d_3
  std::vector<Mat3> velocity_gradient; // grid velocity gradient at x, written by g2p
  std::vector<double> volume;          // cell area x thickness
  std::vector<double> basis;           // per particle: support x {R, R_1, R_2}
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

  // Type III state.
  ShearParticles shear;

  // Overwrites `force` with -dPsi/dx for the current positions (Type IV Kirchhoff-Love force plus the
  // Type III tangent-plane part), and fills shear.stress for the grid. Stops at the first degenerate point.
  // For plastic materials each layer point is first return-mapped at the current (trial) state: the
  // return mapping needs the same kinematics as the stress, so it shares this pass.
  ForceFailure compute_forces();
  // After the control points moved: Type III positions (Eq. 4.10), director advection
  // d_3 <- (I + dt grad v) d_3, and the shear return mapping.
  void update_shear_particles(double dt);
  // Largest accumulated equivalent plastic strain over the layer points (0 when elastic).
  double max_plastic_strain() const;
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
  void build_shear_particles();
  // Type III force of cell c on its support control points (added to out) and its grid stress term.
  bool add_shear_force(size_t c, Vec3* out);
  // Position of shear particle c (thesis Eq. 4.10) and the surface tangents a_1, a_2 there.
  Vec3 shear_particle_frame(size_t c, Vec3& a1, Vec3& a2) const;

  nurbs::NurbsSurface reference_;
  ShellMaterial material_;
  LayerRule layers_;
  int support_size_ = 0;
  size_t num_cells_ = 0, points_per_cell_ = 0;
  std::vector<int> support_;        // cells x support_size control point indices
  std::vector<Vec2> param_;         // in-plane points, grouped by cell
  std::vector<Vec2> cell_center_;   // parameter centre of each cell
  std::vector<double> basis_;       // in-plane points x support x {R, R1, R2, R11, R12, R22}
  std::vector<ReferenceLayer> ref_; // in-plane points x layers: rest metric (rewritten by plasticity)
  std::vector<double> plastic_strain_;  // in-plane points x layers, only for plastic materials
  std::vector<double> volume_;      // in-plane points x layers: V_q
  // Deterministic gather of per-cell forces: control point c receives cell_force_[gather_[k]] for
  // k in gather_offsets_[c] .. gather_offsets_[c+1].
  std::vector<Vec3> cell_force_;
  std::vector<int> gather_offsets_, gather_;
};

}  // namespace shellfrac::shell
