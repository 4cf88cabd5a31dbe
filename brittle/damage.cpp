#include "brittle/damage.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::brittle {

double brittleness(double failure_stress, double fracture_energy, double youngs_modulus, double characteristic_length) {
  const double hbar = failure_stress * failure_stress / (2.0 * youngs_modulus * fracture_energy);
  const double hl = hbar * characteristic_length;
  if (!(hl > 0.0) || !(hl < 1.0)) return -1.0;
  return hl / (1.0 - hl);
}

double rankine_damage(double effective_stress, double failure_stress, double h) {
  if (!(effective_stress > failure_stress)) return 0.0;
  if (effective_stress >= failure_stress * (1.0 + 1.0 / h)) return 1.0;
  return std::min(1.0, (1.0 + h) * (1.0 - failure_stress / effective_stress));
}

Mat3d neo_hookean_kirchhoff(const Mat3d& F, double mu, double lambda) {
  const double J = F.determinant();
  return mu * (F * F.transpose() - Mat3d::Identity()) + lambda * std::log(J) * Mat3d::Identity();
}

Mat3d weaken_tensile_part(const Mat3d& s, double c, double* largest) {
  Eigen::SelfAdjointEigenSolver<Mat3d> eig(s);
  Eigen::Vector3d l = eig.eigenvalues();  // ascending
  if (largest) *largest = l[2];
  for (int i = 0; i < 3; ++i)
    if (l[i] > 0) l[i] *= 1.0 - c;  // thesis Eq. 2.30
  const Mat3d& q = eig.eigenvectors();
  return q * l.asDiagonal() * q.transpose();  // Eq. 2.31
}

double largest_eigenvalue_bound(const Mat3d& s) {
  double bound = -std::numeric_limits<double>::infinity();
  for (int r = 0; r < 3; ++r)
    bound = std::max(bound, s(r, r) + std::abs(s(r, (r + 1) % 3)) + std::abs(s(r, (r + 2) % 3)));
  return bound;
}

Mat3d damage_step(const Mat3d& F, double rest_volume, double mu, double lambda, double failure_stress,
                  double h, DamageRule rule, double residual, double time, ParticleDamage& st) {
  const double J = F.determinant();
  const Mat3d kirchhoff = mu * (F * F.transpose() - Mat3d::Identity()) + lambda * std::log(J) * Mat3d::Identity();
  const Mat3d effective = kirchhoff / J;  // sigma_bar: the stress as if undamaged (sec. 2.3.2)
  // Below sigma_f c_bar = 0; with nothing left from earlier steps the stress is the undamaged one.
  if (largest_eigenvalue_bound(effective) <= failure_stress && (rule == DamageRule::Healing || st.c == 0.0)) {
    st.c = 0.0;
    return rest_volume * kirchhoff;
  }
  Eigen::SelfAdjointEigenSolver<Mat3d> eig(effective);
  Eigen::Vector3d l = eig.eigenvalues();
  const double c_bar = rankine_damage(l[2], failure_stress, h);  // sigma_bar = largest principal value
  st.c = rule == DamageRule::Healing ? c_bar : std::max(c_bar, st.c);
  if (st.c > st.c_his) st.c_his = st.c;
  if (st.c_his >= 1.0 && st.tau < 0) st.tau = time;
  if (st.c == 0.0) return rest_volume * kirchhoff;
  const double keep = 1.0 - (1.0 - residual) * st.c;  // Eq. 2.30 with a residual share r (0: the thesis)
  for (int i = 0; i < 3; ++i)
    if (l[i] > 0) l[i] *= keep;  // Eq. 2.29-2.30: tensile part only
  const Mat3d& q = eig.eigenvectors();
  return (rest_volume * J) * (q * l.asDiagonal() * q.transpose());  // V^0 J sigma (Eq. 2.31)
}

bool limit_stretch(Mat3d& F, double limit) {
  const Eigen::JacobiSVD<Mat3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();  // decreasing
  if (!(s[0] > limit) && !(s[2] * limit < 1.0)) return false;
  F = svd.matrixU() * s.cwiseMin(limit).cwiseMax(1.0 / limit).asDiagonal() * svd.matrixV().transpose();
  return true;
}

}  // namespace shellfrac::brittle
