#pragma once
#include <Eigen/Dense>  // all of Core, LU, Geometry: partial includes link-fail only in Release

namespace shellfrac::shell {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Mid-surface derivatives at one parameter point: the covariant tangents a_1, a_2 and the second
// derivatives x_,11 x_,12 x_,22 (thesis Eq. 4.1 and Table 4.1).
struct SurfaceJet {
  Vec3 a1, a2, a11, a12, a22;
};

// The unit normal a_3 = (a_1 x a_2)/|a_1 x a_2| and its parametric derivatives a_3,alpha, which give
// the Kirchhoff-Love covariant basis through the thickness (thesis Eq. 4.3):
//   g_alpha = a_alpha + xi3 a_3,alpha,   g_3 = a_3.
struct NormalJet {
  Vec3 n;           // a_3
  double length;    // |a_1 x a_2|
  Vec3 dv1, dv2;    // d(a_1 x a_2)/d xi_alpha
  Vec3 dn1, dn2;    // a_3,alpha
};

// Builds the mid-surface jet from control point positions and basis derivatives:
// a_alpha = sum_s R_s,alpha x_s, x_,alpha beta = sum_s R_s,alpha beta x_s.
// d[stride * i + {0..4}] = {R_,1 R_,2 R_,11 R_,12 R_,22} of control point i, for n control points.
SurfaceJet surface_jet(const Vec3* const* points, const double* d, int n, int stride = 5);

// Returns false (and leaves j untouched) when the tangents are parallel (|a_1 x a_2| ~ 0).
bool normal_jet(const SurfaceJet& s, NormalJet& j);

// Covariant KL basis G = [g_1 g_2 g_3] at thickness coordinate xi3 (thesis Eq. 4.3, 4.5).
Mat3 kl_basis(const SurfaceJet& s, const NormalJet& j, double xi3);

// Reverse-mode derivative of a linear functional of the KL bases. Given, for each layer,
// k_i = dE/dg_i, the caller passes the sums over layers
//   K_alpha = sum_l k_alpha^(l),  C_alpha = sum_l xi3_l k_alpha^(l),  K_3 = sum_l k_3^(l);
// this returns dE/d(a1, a2, a11, a12, a22), including the normal's dependence on the tangents and on
// the second derivatives (the analytic dF^KL/dx_p of thesis Eq. 4.8).
struct JetGradient {
  Vec3 a1, a2, a11, a12, a22;
};
JetGradient kl_basis_adjoint(const SurfaceJet& s, const NormalJet& j, const Vec3& K1, const Vec3& K2,
                             const Vec3& C1, const Vec3& C2, const Vec3& K3);

}  // namespace shellfrac::shell
