#include "shell/shear_model.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace shellfrac::shell {

void qr_oriented(const Mat3& F, Mat3& Q, Mat3& R) {
  const Vec3 q1 = F.col(0).normalized();
  const Vec3 q2 = (F.col(1) - q1.dot(F.col(1)) * q1).normalized();
  Q.col(0) = q1;
  Q.col(1) = q2;
  Q.col(2) = q1.cross(q2);
  R = Q.transpose() * F;
  R(1, 0) = R(2, 0) = R(2, 1) = 0.0;  // exact zeros below the diagonal
}

double shear_energy_density(const Mat3& R, const ShearParams& p) {
  const double r13 = R(0, 2), r23 = R(1, 2), r33 = R(2, 2);
  double e = 0.5 * p.gamma * (r13 * r13 + r23 * r23);
  if (r33 < 1.0) e += p.k / 3.0 * (1.0 - r33) * (1.0 - r33) * (1.0 - r33);
  return e;
}

Vec3 shear_energy_gradient(const Mat3& R, const ShearParams& p) {
  const double r33 = R(2, 2);
  return {p.gamma * R(0, 2), p.gamma * R(1, 2), r33 < 1.0 ? -p.k * (1.0 - r33) * (1.0 - r33) : 0.0};
}

Mat3 shear_pk1(const Mat3& F, const ShearParams& p) {
  Mat3 Q, R;
  qr_oriented(F, Q, R);
  // With A = dpsi/dR (upper triangular) and B = A R^T, a variation dF gives
  // dpsi = C : (Q^T dF R^-1) with C = upper(B) + strict_upper(B)^T, hence P = Q C R^-T.
  Mat3 A = Mat3::Zero();
  A.col(2) = shear_energy_gradient(R, p);
  const Mat3 B = A * R.transpose();
  Mat3 C = Mat3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      C(i, j) = B(i, j);
      if (j > i) C(j, i) = B(i, j);
    }
  return Q * C * R.inverse().transpose();
}

Vec3 shear_return_map(const Mat3& F, const ShearParams& p) {
  Mat3 Q, R;
  qr_oriented(F, Q, R);
  Vec3 r = R.col(2);
  if (r.z() > 1.0) {
    r = Vec3(0, 0, 1);  // separated: no shear, no compression
  } else {
    const double shear = std::hypot(r.x(), r.y());
    const double limit = p.gamma > 0 ? p.friction * p.k * (1.0 - r.z()) * (1.0 - r.z()) / p.gamma : 0.0;
    if (shear > limit) {
      const double s = shear > 0 ? limit / shear : 0.0;
      r.x() *= s;
      r.y() *= s;
    }
  }
  return Q * r;
}

}  // namespace shellfrac::shell
