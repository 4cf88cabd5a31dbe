#include "shell/plasticity.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace shellfrac::shell {

namespace {

using Mat2 = Eigen::Matrix2d;

struct ElasticState {
  Mat2 L;         // Cholesky factor of the deformed covariant metric c = L L^T
  Mat2 W;         // eigenvectors of S = L^T G_p L
  double s1, s2;  // eigenvalues of S: squared elastic principal in-plane stretches
};

ElasticState elastic_state(const Vec3& g1, const Vec3& g2, const ReferenceLayer& rest) {
  Mat2 c, P;
  c << g1.squaredNorm(), g1.dot(g2), g1.dot(g2), g2.squaredNorm();
  P << rest.g11, rest.g12, rest.g12, rest.g22;
  ElasticState e;
  e.L = c.llt().matrixL();
  const Mat2 S = e.L.transpose() * P * e.L;
  Eigen::SelfAdjointEigenSolver<Mat2> eig(S);
  e.W = eig.eigenvectors();
  e.s1 = eig.eigenvalues()[0];
  e.s2 = eig.eigenvalues()[1];
  return e;
}

// Principal plane-stress Kirchhoff stresses for elastic log strains e1, e2 (Neo-Hookean, condensed fibre).
void principal_stress(double e1, double e2, double mu, double lambda, double& t1, double& t2) {
  const double J = std::exp(e1 + e2);
  const double l3 = condensed_fibre_stretch(J, mu, lambda);
  const double p = lambda * std::log(J * l3);
  t1 = mu * (std::exp(2 * e1) - 1) + p;
  t2 = mu * (std::exp(2 * e2) - 1) + p;
}

double mises(double t1, double t2) { return std::sqrt(std::max(0.0, t1 * t1 - t1 * t2 + t2 * t2)); }

}  // namespace

double von_mises_stress(const Vec3& g1, const Vec3& g2, double mu, double lambda, const ReferenceLayer& rest) {
  const ElasticState s = elastic_state(g1, g2, rest);
  double t1, t2;
  principal_stress(0.5 * std::log(s.s1), 0.5 * std::log(s.s2), mu, lambda, t1, t2);
  return mises(t1, t2);
}

bool von_mises_return(const Vec3& g1, const Vec3& g2, double mu, double lambda, const PlasticityParams& p,
                      ReferenceLayer& rest, double& alpha) {
  // Cheap elastic check first: principal stresses from the invariants of the mixed tensor tau^a_b,
  // q^2 = (t1 + t2)^2 - 3 t1 t2.
  const InPlaneStress st = neo_hookean_in_plane(g1, g2, rest, mu, lambda, TransverseModel::Condensed);
  if (!st.ok) return false;  // degenerate; reported by the force evaluation
  const double c11 = g1.squaredNorm(), c12 = g1.dot(g2), c22 = g2.squaredNorm();
  const double trace = st.t11 * c11 + 2 * st.t12 * c12 + st.t22 * c22;
  const double det = (st.t11 * st.t22 - st.t12 * st.t12) * (c11 * c22 - c12 * c12);
  if (trace * trace - 3 * det <= std::pow(p.yield_stress + p.hardening * alpha, 2)) return false;

  const ElasticState s = elastic_state(g1, g2, rest);
  const double e1 = 0.5 * std::log(s.s1), e2 = 0.5 * std::log(s.s2);
  double t1, t2;
  principal_stress(e1, e2, mu, lambda, t1, t2);
  const double q = mises(t1, t2);
  if (q <= p.yield_stress + p.hardening * alpha) return false;

  // Plane-stress return (Simo & Taylor's projection) in principal log-strain space with the Hencky
  // moduli, exact for small elastic strains as in metals. The flow e^p' = dg P tau, with the von Mises
  // matrix P (q^2 = tau^T P tau), decouples in the sum/difference modes of the principal stresses:
  //   tau_s = (t1 + t2)/sqrt2 relaxes as 1 / (1 + dg E / (2 (1 - nu))),  tau_d = (t1 - t2)/sqrt2 as
  //   1 / (1 + 3 mu dg), and the equivalent plastic strain grows by dg q (plastic work / q).
  // The trial stress of the return is the Hencky one of the same log strains, so that the corrected
  // strains are exact for it; the yield check above used the Neo-Hookean stress the forces use.
  const double E = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
  const double h1 = E / (1 - nu * nu) * (e1 + nu * e2), h2 = E / (1 - nu * nu) * (e2 + nu * e1);
  const double ts = (h1 + h2) / std::sqrt(2.0), td = (h1 - h2) / std::sqrt(2.0);
  auto returned_q = [&](double dg) {
    const double s = ts / (1 + dg * E / (2 * (1 - nu))), d = td / (1 + 3 * mu * dg);
    return std::sqrt(0.5 * s * s + 1.5 * d * d);
  };
  auto excess = [&](double dg) {
    const double qr = returned_q(dg);
    return qr - (p.yield_stress + p.hardening * (alpha + dg * qr));
  };
  double lo = 0, hi = 1.0 / (mu + p.hardening);
  for (int i = 0; i < 200 && excess(hi) > 0; ++i) hi *= 2;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) > 0 ? lo : hi) = mid;
  }
  const double dg = 0.5 * (lo + hi);
  const double s_ret = ts / (1 + dg * E / (2 * (1 - nu))), d_ret = td / (1 + 3 * mu * dg);
  const double r1 = (s_ret + d_ret) / std::sqrt(2.0), r2 = (s_ret - d_ret) / std::sqrt(2.0);
  alpha += dg * returned_q(dg);
  // Elastic log strains after the flow: e = e_trial - dg P tau.
  const double f1 = e1 - dg * (r1 - 0.5 * r2), f2 = e2 - dg * (r2 - 0.5 * r1);

  // Corrected elastic stretches along the same principal directions: S' = W diag(s') W^T, and the rest
  // metric from S' = L^T G_p L.
  const double s1 = std::exp(2 * f1), s2 = std::exp(2 * f2);
  const Mat2 Snew = s.W * Eigen::Vector2d(s1, s2).asDiagonal() * s.W.transpose();
  const Mat2 Linv = s.L.inverse();
  const Mat2 P = Linv.transpose() * Snew * Linv;
  rest.g11 = P(0, 0);
  rest.g12 = 0.5 * (P(0, 1) + P(1, 0));
  rest.g22 = P(1, 1);
  rest.sqrt_det = 1.0 / std::sqrt(rest.g11 * rest.g22 - rest.g12 * rest.g12);
  return true;
}

}  // namespace shellfrac::shell
