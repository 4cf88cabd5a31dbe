#include "shell/in_plane_stress.hpp"

#include <Eigen/LU>
#include <cmath>

namespace shellfrac::shell {

Mat3 neo_hookean_pk1(const Mat3& F, double mu, double lambda) {
  const double J = F.determinant();
  const Mat3 FinvT = F.inverse().transpose();
  return mu * (F - FinvT) + lambda * std::log(J) * FinvT;
}

double neo_hookean_energy(const Mat3& F, double mu, double lambda) {
  const double lnJ = std::log(F.determinant());
  return 0.5 * mu * ((F.transpose() * F).trace() - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
}

Mat3 contravariant_components(const Mat3& sigma, const Mat3& G) {
  const Mat3 Ginv = G.inverse();  // rows are the dual basis vectors g^i
  return Ginv * sigma * Ginv.transpose();
}

Mat3 contravariant_components_9x9(const Mat3& sigma, const Mat3& G) {
  // Column (i, j) of the system matrix is vec(g_i (x) g_j); unknowns zeta = (sigma^ij).
  Mat9 A;
  Vec9 b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Mat3 outer = G.col(i) * G.col(j).transpose();
      A.col(3 * i + j) = Eigen::Map<const Vec9>(outer.data());
    }
  b = Eigen::Map<const Vec9>(sigma.data());
  const Vec9 zeta = A.fullPivLu().solve(b);
  Mat3 S;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S(i, j) = zeta[3 * i + j];
  return S;
}

Mat3 in_plane_part(const Mat3& sigma, const Mat3& G) {
  Mat3 S = contravariant_components(sigma, G);
  S.row(2).setZero();
  S.col(2).setZero();
  return G * S * G.transpose();
}

ReferenceLayer reference_layer(const Mat3& Gbar) {
  const double g11 = Gbar.col(0).squaredNorm(), g12 = Gbar.col(0).dot(Gbar.col(1)),
               g22 = Gbar.col(1).squaredNorm();
  const double det = g11 * g22 - g12 * g12;
  return {g22 / det, -g12 / det, g11 / det, std::sqrt(det)};
}

double condensed_fibre_stretch(double J, double mu, double lambda) {
  // h(l) = mu (l^2 - 1) + lambda (ln l + ln J) is increasing in l > 0; Newton from the linearised root.
  const double lnJ = std::log(J);
  double l = std::exp(-lambda * lnJ / (2.0 * mu + lambda));
  for (int it = 0; it < 30; ++it) {
    const double h = mu * (l * l - 1.0) + lambda * (std::log(l) + lnJ);
    const double dh = 2.0 * mu * l + lambda / l;
    double next = l - h / dh;
    if (next <= 0) next = 0.5 * l;  // keep the stretch positive
    const bool converged = std::abs(next - l) <= 1e-15 * l;
    l = next;
    if (converged) break;
  }
  return l;
}

namespace {

double fibre_stretch(TransverseModel model, double J, double mu, double lambda, double given) {
  switch (model) {
    case TransverseModel::Condensed: return condensed_fibre_stretch(J, mu, lambda);
    case TransverseModel::Given: return given;
    case TransverseModel::Rigid: break;
  }
  return 1.0;
}

}  // namespace

InPlaneStress neo_hookean_in_plane(const Vec3& g1, const Vec3& g2, const ReferenceLayer& ref, double mu,
                                   double lambda, TransverseModel model, double given_lambda3) {
  InPlaneStress s{};
  const double c11 = g1.squaredNorm(), c12 = g1.dot(g2), c22 = g2.squaredNorm();
  const double det = c11 * c22 - c12 * c12;
  if (!(det > 0)) return s;
  s.J = std::sqrt(det) / ref.sqrt_det;
  if (!(s.J > 0) || !std::isfinite(s.J)) return s;
  const double inv = 1.0 / det;
  const double i11 = c22 * inv, i12 = -c12 * inv, i22 = c11 * inv;  // deformed g^{ab}
  s.lambda3 = fibre_stretch(model, s.J, mu, lambda, given_lambda3);
  const double p = lambda * std::log(s.J * s.lambda3);
  s.t11 = mu * (ref.g11 - i11) + p * i11;
  s.t12 = mu * (ref.g12 - i12) + p * i12;
  s.t22 = mu * (ref.g22 - i22) + p * i22;
  s.ok = true;
  return s;
}

double neo_hookean_in_plane_energy(const Vec3& g1, const Vec3& g2, const ReferenceLayer& ref, double mu,
                                   double lambda, TransverseModel model, double given_lambda3) {
  const double c11 = g1.squaredNorm(), c12 = g1.dot(g2), c22 = g2.squaredNorm();
  const double J = std::sqrt(c11 * c22 - c12 * c12) / ref.sqrt_det;
  const double l3 = fibre_stretch(model, J, mu, lambda, given_lambda3);
  // tr(C) = gbar^{ab} g_ab + lambda_3^2, ln det F = ln(J lambda_3)   (Eq. 2.3)
  const double trC = ref.g11 * c11 + 2.0 * ref.g12 * c12 + ref.g22 * c22 + l3 * l3;
  const double lnJ = std::log(J * l3);
  return 0.5 * mu * (trC - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
}

}  // namespace shellfrac::shell
