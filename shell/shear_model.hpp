#pragma once
#include "shell/kinematics.hpp"

namespace shellfrac::shell {

// Shearing/compression model of the Type-III particles (thesis sec. 4.3.2, which defers to Guo et al.
// 2018; the QR-based model of Jiang et al. 2017). With F = d D^-1 (d = [a_1 a_2 d_3], d_3 the elastic
// director) written as F = Q R, R upper triangular and Q a rotation, the energy density depends only
// on R's third column:
//   psi = gamma / 2 (r13^2 + r23^2) + k / 3 (1 - r33)^3   (the second term only while r33 < 1).
// See docs/shear-model.md for the derivation of the stress and the return mapping.
struct ShearParams {
  double gamma = 0;     // shear stiffness [Pa]
  double k = 0;         // compression stiffness [Pa]
  double friction = 0;  // Coulomb coefficient c_F between the shear and the normal compression
};

// QR with q_1 = f_1/|f_1|, q_2 from Gram-Schmidt and q_3 = q_1 x q_2, so det Q = +1 and r33 keeps the
// sign of the director (a flipped director gives r33 < 0). Requires independent first two columns.
void qr_oriented(const Mat3& F, Mat3& Q, Mat3& R);

double shear_energy_density(const Mat3& R, const ShearParams& p);
// dpsi/dR (non-zero only in the third column).
Vec3 shear_energy_gradient(const Mat3& R, const ShearParams& p);
// First Piola-Kirchhoff stress P = dpsi/dF = Q C R^-T (C assembled from dpsi/dR R^T, see docs).
Mat3 shear_pk1(const Mat3& F, const ShearParams& p);

// Return mapping of the third column of R: separation (r33 > 1 resets r13 = r23 = 0, r33 = 1) and
// Coulomb friction (|(r13, r23)| <= c_F k (1 - r33)^2 / gamma). Returns the elastic third column of F,
// i.e. the corrected director Q R_e e_3.
Vec3 shear_return_map(const Mat3& F, const ShearParams& p);

}  // namespace shellfrac::shell
