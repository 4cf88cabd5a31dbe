#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "nurbs/nurbs_surface.hpp"
#include "shell/basis_chain.hpp"
#include "shell/basis_stiffness.hpp"
#include "shell/crack_bases.hpp"
#include "shell/damage.hpp"
#include "shell/force_gather.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/kinematics.hpp"
#include "shell/material_state.hpp"
#include "shell/mls_basis.hpp"
#include "shell/patch_particles.hpp"
#include "shell/patch_quadrature.hpp"
#include "shell/plasticity.hpp"
#include "shell/quadrature.hpp"
#include "shell/shear_model.hpp"
#include "shell/stress_model.hpp"
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell {

using Vec2 = Eigen::Vector2d;

// Material constants a shell patch needs for its forces.
struct ShellMaterial {
  double mu = 0, lambda = 0;  // Lamé parameters (thesis Eq. 2.4)
  double density = 0;         // kg / m^3
  double thickness = 0;       // tau
  TransverseModel transverse = TransverseModel::Condensed;
  StressModel stress_model = StressModel::KirchhoffLove;
  ShearParams shear;          // Type-III shearing/compression model
  PlasticityParams plasticity;  // Type-IV von Mises plasticity (metal sheets)
  FractureParams fracture;      // Type-IV Rankine damage (thesis sec. 4.4.1)
  double brittleness = 0;       // H of thesis Eq. 2.28, from sigma_f, G_f, E and l_ch (set_brittleness)
  double shear_mass_share = 0.5;  // share of each cell's mass on its Type-III particle, in (0, 1)
};

// Share of a cell's mass carried by its Type-III particle; the control points carry the rest. Type III
// particles must carry mass (thesis sec. 4.3.2: Types I-III transfer mass and momentum): their stress
// reaches grid nodes that no control point touches, and a massless node would drop that force and break
// momentum conservation. The thesis gives no value; this is the default (ShellMaterial::shear_mass_share).
inline constexpr double kShearParticleMassShare = 0.5;
static_assert(kShearParticleMassShare == ShellMaterial{}.shear_mass_share);

// Where a force evaluation failed: an inverted or degenerate quadrature point.
struct ForceFailure {
  bool failed = false;
  size_t quadrature_point = 0;  // in-plane point index
  int layer = 0;
  Vec2 parameter = Vec2::Zero();
  std::string reason;
};

// Which implementation of the Type IV force compute_forces uses (shell/type4_kernel.hpp). Batched: NURBS
// points eight at a time in vector lanes, their rest metrics and volumes stored in lane order, MLS points
// in lanes of their own grouped by support size (linear and oversized supports by the scalar code);
// BatchedGathered: the same kernel gathering rest metrics and volumes per lane (what the lane order saves,
// for bench_forces); BatchedScalarMls: NURBS lanes with every MLS point by the scalar code (what the MLS
// lanes save); Scalar: every point by the scalar reference (for tests and comparisons). All agree to
// round-off.
enum class ForceKernel { Batched, BatchedGathered, BatchedScalarMls, Scalar };

// One NURBS patch of a Kirchhoff-Love shell, discretised as in thesis sec. 4.3:
//  - Type II particles: the control points (position, velocity, lumped mass) — the advected DOFs;
//  - Type III particles: one per cell, for shear and compression;
//  - Type IV particles: massless quadrature points, a stencil per cell on 1 or 3 layers, whose basis
//    derivatives (values, first and second) are computed once from their parameter coordinates and
//    reused every step.
// compute_forces() evaluates the Kirchhoff-Love generalised force on every control point
// (thesis Eq. 4.8 with the in-plane stress of sec. 4.5).
//
// The patch is its particles (PatchParticles, which the grid transfers read and write directly) plus
// plain parts, each in its own header: the quadrature and its lane layout, the material state, the
// crack-cut bases, the step stiffness with the added mass, and the force gather. Its methods coordinate
// the parts; the work that needs one part only is a free function next to that part.
class ShellPatch : public PatchParticles {
 public:
  ShellPatch(const nurbs::NurbsSurface& reference, const ShellMaterial& material,
             const QuadratureRule& rule = QuadratureRule{});

  const nurbs::NurbsSurface& reference() const { return reference_; }
  const ShellMaterial& material() const { return material_; }
  // The deformed surface: reference knots and weights with the current control point positions.
  nurbs::NurbsSurface current_surface() const;

  size_t num_control_points() const { return x.size(); }
  size_t num_cells() const { return quad_.num_cells; }
  size_t num_inplane_points() const { return quad_.param.size(); }
  size_t num_quadrature_points() const { return quad_.param.size() * quad_.num_layers(); }
  int num_layers() const { return static_cast<int>(quad_.num_layers()); }

  // Overwrites `force` with -dPsi/dx for the current positions (Type IV Kirchhoff-Love force plus the
  // Type III tangent-plane part), and fills shear.stress for the grid. Stops at the first degenerate point.
  // For plastic materials each layer point is first return-mapped at the current (trial) state: the
  // return mapping needs the same kinematics as the stress, so it shares this pass.
  ForceFailure compute_forces();
  void set_force_kernel(ForceKernel k) { force_kernel_ = k; }
  ForceKernel force_kernel() const { return force_kernel_; }
  // After the control points moved: Type III positions (Eq. 4.10), director advection
  // d_3 <- (I + dt grad v) d_3, and the shear return mapping.
  void update_shear_particles(double dt);
  // Largest accumulated equivalent plastic strain over the layer points (0 when elastic).
  double max_plastic_strain() const;
  // Accumulated equivalent plastic strain per layer point, index q * num_layers() + layer (empty when elastic).
  const std::vector<double>& plastic_strain_values() const { return state_.plastic_strain; }
  // Total elastic energy Psi = sum_q V_q psi(F_q) of the current configuration.
  double elastic_energy() const;
  // Per in-plane point, the largest absolute principal in-plane Cauchy stress on the mid-surface of the
  // current configuration, without damage (a diagnostic: stress spikes at seams, maps).
  std::vector<double> mid_surface_stress() const;
  // Reference volume of the shell (sum of V_q), equal to thickness x area up to quadrature error.
  double reference_volume() const;
  // Kirchhoff-Love deformation gradient F^KL = sum_i g_i^KL (x) Gbar^i of every layer point (thesis Eq. 4.5),
  // recomputed from the current control points with the kinematics of the force pass (the patch stores no
  // F): index q * num_layers() + layer. The third column maps the reference normal to the current unit
  // normal a_3 (no fibre stretch). Points that carry no stress (basis level Rigid or Removed) or whose
  // tangents are parallel get NaN. Total F against the reference surface (plastic flow not removed).
  std::vector<Mat3> deformation_gradients() const;

  // Fracture state of the Type IV points (thesis sec. 4.4.1), present only when material.fracture is on.
  bool fractures() const { return state_.fractures(); }
  // Failure stress sigma_f and brittleness H (thesis Eq. 2.28) of in-plane point q (all layers). H depends
  // on sigma_f and on the grid's characteristic length, so the caller computes both; scene regions
  // override the material values point by point.
  double failure_stress(size_t q) const { return state_.failure_stress[q]; }
  double brittleness(size_t q) const { return state_.brittleness[q]; }
  void set_failure_stress(size_t q, double sigma_f, double brittleness) {
    state_.failure_stress[q] = sigma_f;
    state_.brittleness[q] = brittleness;
  }
  // Sets the material's brittleness at every point (before regions override it).
  void set_brittleness(double h) {
    material_.brittleness = h;
    std::fill(state_.brittleness.begin(), state_.brittleness.end(), h);
  }
  // Parameter coordinates of all in-plane points (the crack extraction's samples).
  const std::vector<Vec2>& inplane_parameters() const { return quad_.param; }
  // Typical spacing of the in-plane points in parameter space.
  double parameter_spacing() const;
  // Damage c and its history c_his of layer point (q, layer).
  double damage(size_t q, int layer) const { return state_.damage[q * quad_.num_layers() + static_cast<size_t>(layer)]; }
  double damage_history(size_t q, int layer) const {
    return state_.damage_history[q * quad_.num_layers() + static_cast<size_t>(layer)];
  }
  // All of c and c_his, index q * num_layers() + layer (empty when the material does not fracture).
  const std::vector<double>& damage_values() const { return state_.damage; }
  const std::vector<double>& damage_history_values() const { return state_.damage_history; }
  // Per in-plane point: 1 when the damage history of any layer reached 1 (the crack extraction's input).
  std::vector<unsigned char> fully_damaged_points() const;
  // How many in-plane points fully_damaged_points() marks, without building the list.
  size_t num_fully_damaged_points() const;
  double max_damage() const;

  // Cracks (thesis sec. 4.6). After the crack graph gained edges [first_new_edge, end), every Type III
  // and Type IV point whose support those edges touch is re-examined: if the crack separates it from a
  // control point of its NURBS support it switches to an MLS basis over the control points it can see
  // (segment test in parameter space). The index must outlive the patch's use of it.
  // Points whose MLS fit fails go down the fallback chain (shell/basis_chain.hpp): they are never dropped.
  CrackUpdate update_crack(const crack2d::CrackIndex& index, size_t first_new_edge, const MlsSettings& settings);
  // The same with the fallback chain's own settings (chain.mls replaces `settings` above).
  CrackUpdate update_crack(const crack2d::CrackIndex& index, size_t first_new_edge, const BasisChainSettings& chain);
  const crack2d::CrackIndex* crack() const { return cut_.crack; }
  size_t num_mls_points() const { return cut_.num_mls_points; }
  // MLS points whose forces the batched kernel computes (the rest of them run the scalar kernel).
  size_t num_batched_mls_points() const { return static_cast<size_t>(std::count(mls_lanes_.batched.begin(), mls_lanes_.batched.end(), 1)); }
  // Material without a basis (census().failures); 0 unless the fallback chain failed somewhere.
  size_t num_mls_failures() const { return cut_.census.failures; }
  const BasisCensus& census() const { return cut_.census; }
  // Basis level of in-plane point q / shear particle c.
  BasisLevel point_level(size_t q) const;
  BasisLevel shear_level(size_t c) const;
  // Parameter location of control point k (its Greville point) and of shear particle c (cell centre).
  Vec2 control_parameter(size_t k) const { return quad_.control_grid.point(static_cast<int>(k)); }
  const Vec2& shear_parameter(size_t c) const { return quad_.cell_center[c]; }
  // Per control point / shear particle: non-zero when it takes part in an MLS basis (the particles
  // whose grid nodes get phantom copies, thesis sec. 4.7.1).
  const std::vector<unsigned char>& control_near_crack() const { return cut_.control_near_crack; }
  const std::vector<unsigned char>& shear_near_crack() const { return cut_.shear_near_crack; }
  // Per cell: non-zero when some in-plane point of it has a fallback basis (point_level not Nurbs).
  const std::vector<unsigned char>& cut_cells() const { return cut_.cut_cells; }
  // Current mid-surface point at parameter uv (render vertices, thesis sec. 4.9.3): NURBS, or, when the
  // crack separates uv from part of its NURBS support, the same fallback chain as the quadrature points,
  // so a vertex never averages across a crack. level == Removed: uv lies in a fragment without control
  // points; position is then the NURBS one and meaningless, and faces using the vertex should be dropped.
  struct SurfacePoint {
    Vec3 position = Vec3::Zero();
    BasisLevel level = BasisLevel::Nurbs;
  };
  SurfacePoint surface_point(const Vec2& uv, BasisChainWork& work) const;
  // What surface_point(uv) reads of the current state: the position is sum_k R[k] x[index[k]] + offset.
  // It depends on the reference surface and the crack only, so it can be kept while they do not change
  // (a render mesh's vertices between frames). offset is non-zero for a Rigid fallback only.
  struct SurfaceStencil {
    BasisLevel level = BasisLevel::Nurbs;
    std::vector<int> index;
    std::vector<double> R;
    Vec3 offset = Vec3::Zero();
  };
  // Fills `out` (its vectors are reused) for the point at uv.
  void surface_stencil(const Vec2& uv, BasisChainWork& work, SurfaceStencil& out) const;
  // sum_k R[k] x[index[k]] + offset, in surface_point's order of summation.
  Vec3 stencil_position(const int* index, const double* R, size_t count, const Vec3& offset) const {
    Vec3 p = Vec3::Zero();
    for (size_t k = 0; k < count; ++k) p += R[k] * x[static_cast<size_t>(index[k])];
    return p + offset;
  }
  // surface_point(uv).position with per-thread scratch of its own (`work` is not used any more).
  Vec3 position_at(const Vec2& uv, MlsBasis& work) const;

  // Parameter coordinate and basis (value per support control point) of in-plane point q; support
  // control point indices of its cell.
  const Vec2& parameter(size_t q) const { return quad_.param[q]; }
  const int* support(size_t cell) const { return quad_.cell_support(cell); }
  int support_size() const { return quad_.support_size; }
  size_t cell_of(size_t q) const { return quad_.cell_of(q); }

  // r_33 of the QR decomposition of cell c's Type III F = [a_1 a_2 d_3] D^-1 (the director's normal stretch).
  double director_stretch(size_t c) const;

  // How stiff the current bases make the explicit step (shell/basis_stiffness.hpp): the largest row sum
  // per mass of the basis-gradient products, membrane and bending, now and for the uncut NURBS bases. MLS
  // fits next to crack junctions have gradients several times a NURBS one's (docs/mls.md).
  const BasisStiffness& basis_stiffness() const { return stiffness_.current; }
  const BasisStiffness& reference_basis_stiffness() const { return stiffness_.reference; }
  // sqrt(reference / current) of each term, at most 1: the factors on the membrane and bending wave bounds.
  double membrane_step_scale() const;
  double bending_step_scale() const;

  // Selective mass scaling beside cracks: after every basis change the control points whose basis
  // stiffness per mass exceeds the uncut sheet's get the least added mass that brings them back to it,
  // within `budget` x the patch's control-point mass; beyond the budget the stiffest points keep a ratio
  // kappa > 1 and the step shrinks by 1 / sqrt(kappa). 0 (the default) adds none. The added mass moves
  // with the point (World::refresh_control_mass) and carries momentum like the rest.
  void set_mass_scaling_budget(double budget) { stiffness_.mass_scaling_budget = budget; }
  const std::vector<double>& added_mass() const { return stiffness_.added_mass; }
  double added_mass_total() const;
  double control_mass_total() const;

 private:
  void build_masses();
  void build_shear_particles();
  // The basis a point uses: its support control points, basis values (stride: R, R_1, R_2[, 2nd
  // derivatives]) and where its forces on them go (the cell's slots, or its MLS support's own).
  struct BasisView {
    int n;
    const int* index;
    const double* basis;
    int stride;
  };
  static constexpr int kShearStride = 3;  // R, R_1, R_2 per support control point of a NURBS shear particle
  BasisView point_basis(size_t q) const;
  BasisView slot_view(int32_t slot) const;
  // Mid-surface jet of in-plane point q from its NURBS or MLS basis (pts: scratch).
  SurfaceJet point_jet(size_t q, std::vector<const Vec3*>& pts) const;
  BasisView shear_basis(size_t c) const;
  // Where the forces of in-plane point q (shear particle c) on its support control points are gathered:
  // its cell's slots, or its MLS support's own (written by compute_forces only).
  Vec3* point_force_target(size_t q);
  Vec3* shear_force_target(size_t c);
  // Type III force of cell c on its support control points and its grid stress term.
  bool add_shear_force(size_t c);
  // The fallback chain at xi over the current crack, and its result as a support (stride kBasisStride).
  PointFit fit_chain(const Vec2& xi, BasisChainWork& work) const;
  void fill_support(const PointFit& fit, const MlsBasis& basis, MlsSupport& out) const;
  // Position from a support: sum R_k x_k (+ the rigid offset).
  Vec3 support_position(const MlsSupport& m) const;
  // True when the crack separates xi from any control point of the NURBS support of `cell`.
  bool nurbs_support_cut(const Vec2& xi, size_t cell, const crack2d::CrackIndex& index) const;
  // The census of the whole patch's bases (a point can move down the chain when the crack around it grows).
  BasisCensus count_bases() const;
  // Groups the MLS points the batched kernel can take into lanes (mls_lanes_), after every basis change.
  void build_mls_lanes();
  // The Type IV forces of the MLS points in mls_lanes_ (into their supports' own slots); a failing lane
  // marks its cell in cell_failed.
  void mls_batch_forces(const Type4Data& data, bool with_director, std::vector<unsigned char>& cell_failed);
  // The patch's arrays and constants as the Type IV kernels read them.
  Type4Data type4_data();
  // Position of shear particle c (thesis Eq. 4.10) and the surface tangents a_1, a_2 there.
  Vec3 shear_particle_frame(size_t c, Vec3& a1, Vec3& a2) const;
  // R of the QR decomposition of cell c's Type III F = [a_1 a_2 d_3] D^-1.
  Mat3 director_r(size_t c) const;
  // The row sums of the current bases (shell/basis_stiffness.hpp).
  BasisRows basis_rows() const;

  nurbs::NurbsSurface reference_;
  ShellMaterial material_;
  // The parts (each a plain struct in its own header; the free functions there work on them):
  PatchQuadrature quad_;        // Type IV points, their NURBS bases, rest metrics and volumes
  BasisLanes lanes_;            // the same in the batched kernel's lane order
  PointMaterialState state_;    // plastic strain, damage and its history, per-point strength
  CrackBases cut_;              // fallback bases of the points a crack cut off, their census, near-crack flags
  MlsLanes mls_lanes_;          // the fallback-basis points the batched kernel takes, in lanes
  StepStiffness stiffness_;     // basis stiffness for the step bound, and the added mass
  ForceGather gather_;          // per-cell and per-slot force slots and their fixed-order gather
  ForceKernel force_kernel_ = ForceKernel::Batched;
};

}  // namespace shellfrac::shell
