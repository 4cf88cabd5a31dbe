#pragma once
// The Type IV (quadrature point) part of the Kirchhoff-Love force pass (thesis Eq. 4.8, 4.14, sec. 4.4.1):
// mid-surface jet, KL basis through the thickness, in-plane Neo-Hookean stress with the condensed fibre
// stretch, von Mises return and Rankine damage per layer, and the adjoint that maps the stress to forces
// on the support control points.
//
// Two implementations of the same per-point function:
//  - type4_point_force: the scalar reference, one point at a time, any basis (NURBS or MLS);
//  - type4_force_batch: eight NURBS points at once in structure-of-arrays lanes (shell/type4_batch_impl.hpp),
//    compiled for AVX-512, for AVX2+FMA and for the baseline instruction set and picked at run time.
// Each lane's result depends only on that lane's inputs, so the batched results do not depend on how
// points are grouped into batches or threads.
#include <cstddef>
#include <cstdint>

#include "shell/damage.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/kinematics.hpp"
#include "shell/plasticity.hpp"

namespace shellfrac::shell {

// In-plane area ratio J above which a layer point is taken as numerical divergence, not deformation:
// a sheet stretched 30 times in length would have torn long before (compute_forces reports it).
inline constexpr double kRunawayAreaRatio = 1000.0;
// Per-point material state and constants of one patch, as flat arrays indexed q * layers + l (layer
// arrays) or q (point arrays). State arrays are written by the force pass (return mapping, damage).
struct Type4Data {
  double mu = 0, lambda = 0;
  TransverseModel model = TransverseModel::Condensed;
  bool plane_strain = false;  // keep tau^33 = lambda ln J for the damage criterion
  bool mid_surface = false;   // every layer sees the mid-surface metric (MidSurface2D, DirectorF2D)
  bool plastic = false;
  PlasticityParams plasticity;
  bool fracturing = false;
  bool monotone = false;  // DamageRule::Monotone
  double residual = 0;    // FractureParams::residual_stiffness
  int layers = 0;
  const double* xi3 = nullptr;  // layers
  const Vec3* x = nullptr;      // control points
  ReferenceLayer* ref = nullptr;
  const double* volume = nullptr;
  double* plastic_strain = nullptr;  // plastic only
  double* damage = nullptr;          // fracturing only
  double* damage_history = nullptr;  // fracturing only
  const double* failure_stress = nullptr;  // per point, fracturing only
  const double* brittleness = nullptr;     // per point, fracturing only
};

// Failure codes of one point (compute_forces reports them per cell).
enum Type4Status : int { kType4Ok = 0, kType4Degenerate = 1, kType4Runaway = 3 };

// One point's basis: n support control points, per support {R, R_1, R_2, R_11, R_12, R_22} (stride 6).
struct Type4Basis {
  int n;
  const int* index;
  const double* basis;
};

// Scalar reference: adds -dPsi/dx_s of point q to force[s] (s < b.n), updating the point's plastic and
// damage state. membrane: a basis without curvature (every layer on the mid-surface metric). r33: the
// given fibre stretch (TransverseModel::Given).
Type4Status type4_point_force(const Type4Data& d, size_t q, const Type4Basis& b, bool membrane, double r33,
                              Vec3* force);

// Eight lanes of NURBS points (padding lanes inactive).
inline constexpr int kType4Lanes = 8;
inline constexpr int kType4MaxSupport = 64;
inline constexpr int kType4MaxLayers = 4;  // the batched kernel's limit (the layer rules have 1 or 3)
struct Type4Batch {
  int n = 0;                             // support size, the same for every lane
  size_t q[kType4Lanes] = {};            // point of each lane (a valid point also for inactive lanes)
  unsigned active = 0;                   // bit i: lane i is evaluated and its state written back
  const int* support[kType4Lanes] = {};  // support control point indices of each lane
  bool shared_support = false;           // every lane has support[0] (one cell): positions are broadcast
  // Basis derivatives in lanes: basis[(s * 5 + k) * 8 + lane], k = R_1, R_2, R_11, R_12, R_22.
  const double* basis = nullptr;
  double r33[kType4Lanes] = {};          // given fibre stretch per lane
  // Rest metrics ref_lanes[(l * 4 + k) * 8 + lane] (k: g11, g12, g22, 1 / sqrt_det) and volumes
  // volume_lanes[l * 8 + lane] of the batch's points in lanes; null: gathered from Type4Data.
  const double* ref_lanes = nullptr;
  const double* volume_lanes = nullptr;
};
// Per lane: the force on each support control point (-dPsi/dx_s) and the status.
struct Type4BatchResult {
  double force[kType4MaxSupport][3][kType4Lanes];
  int status[kType4Lanes];
};
void type4_force_batch(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out);
// Which implementation type4_force_batch runs on this machine ("avx512", "avx2-fma" or "generic").
const char* type4_batch_isa();

// Damage update and tensile weakening of one layer point's in-plane Kirchhoff stress (thesis sec. 4.4.1,
// Eq. 2.28-2.31): writes c and c_his of layer point ql of point q. tau33 (plane strain): the transverse
// normal stress joins the principal split. detF = J lambda_3.
InPlaneTensor type4_damaged_stress(const Type4Data& d, const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2,
                                   double detF, size_t q, size_t ql, const double* tau33);

namespace detail {
// Scalar return mapping of one lane (called by the batched kernel for lanes near or past the yield
// surface); plain arrays so that the kernel translation units instantiate no shared inline code.
bool type4_return_map_lane(const Type4Data& d, const double g1[3], const double g2[3], size_t ql);
void type4_force_batch_generic(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out);
#if defined(SHELLFRAC_TYPE4_AVX2)
void type4_force_batch_avx2(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out);
void type4_force_batch_avx512(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out);
#endif
}  // namespace detail

}  // namespace shellfrac::shell
