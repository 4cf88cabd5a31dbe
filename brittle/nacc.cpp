#include "brittle/nacc.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace shellfrac::brittle {

using Eigen::Vector2d;
using Eigen::Vector3d;

std::string NaccParams::validate() const {
  std::ostringstream m;
  if (!(std::isfinite(alpha0) && alpha0 < 0))
    m << "alpha0 must be < 0 (alpha0 >= 0 is a material that is broken from the start), got " << alpha0;
  else if (!(std::isfinite(beta) && beta >= 0))
    m << "beta (cohesion) must be >= 0, got " << beta;
  else if (!(std::isfinite(xi) && xi > 0))
    m << "xi (hardening factor) must be > 0, got " << xi;
  else if (!(std::isfinite(friction) && friction > 0))
    m << "friction (M) must be > 0, got " << friction;
  return m.str();
}

const char* to_string(NaccCase c) {
  switch (c) {
    case NaccCase::Elastic: return "elastic";
    case NaccCase::Compression: return "compression";
    case NaccCase::Tension: return "tension";
    case NaccCase::Shear: return "shear";
  }
  return "elastic";
}

double nacc_p0(double alpha, double kappa, const NaccParams& m) {
  return kappa * std::sinh(m.xi * std::max(-alpha, 0.0));
}

namespace {

// Deviatoric Kirchhoff stress of Eq. 10 in principal space: mu J^{-2/3} dev(b), b = s^2.
Vector3d deviator(const Vector3d& s, double mu, double J) {
  const Vector3d b = s.cwiseProduct(s);
  const double c = std::cbrt(J);
  return (mu / (c * c)) * (b.array() - b.sum() / 3.0).matrix();
}

double shear_invariant(const Vector3d& dev) { return std::sqrt(1.5 * dev.squaredNorm()); }

double pressure(double J, double kappa) { return -0.5 * kappa * (J * J - 1.0); }

// J^E at pressure p: the inverse of p = -kappa/2 (J^2 - 1) (Eq. 10), the consistent tip value.
double volume_at_pressure(double p, double kappa) { return std::sqrt(1.0 - 2.0 * p / kappa); }

// The isotropic part t of b^E = d + t 1 (d trace free) with det b^E = J2: the largest root of
// t^3 + e2 t + (e3 - J2) = 0, e2 and e3 the elementary symmetric functions of d. It is the one root with
// every d_i + t > 0. Cardano for one real root (the sign chosen against cancellation), the trigonometric
// form for three, and one Newton step to polish the round-off.
double isotropic_part(const Vector3d& d, double J2) {
  const double P = d[0] * d[1] + d[1] * d[2] + d[0] * d[2];
  const double Q = d[0] * d[1] * d[2] - J2;
  const double D = 0.25 * Q * Q + P * P * P / 27.0;
  double t;
  if (D >= 0) {
    const double u = std::cbrt(-0.5 * Q + (Q < 0 ? 1.0 : -1.0) * std::sqrt(D));
    t = u != 0 ? u - P / (3.0 * u) : 0.0;
  } else {
    const double r = std::sqrt(-P / 3.0);
    const double phi = std::acos(std::clamp(-0.5 * Q / (r * r * r), -1.0, 1.0));
    t = 2.0 * r * std::cos(phi / 3.0);
  }
  const Vector3d f = d.array() + t;
  const double g = f[0] * f[1] * f[2] - J2;
  const double dg = f[0] * f[1] + f[1] * f[2] + f[0] * f[2];
  return dg > 0 ? t - g / dg : t;
}

// Case 3 hardening (sec. 6.2.3): the ray from the ellipse's centre (pc, 0) through the trial state meets
// the ellipse at X = c + l (p - pc, q). Substituting into y = 0 with pc + beta p0 = a and pc - p0 = -a,
// a = (1 + beta) p0 / 2, gives (1 + 2 beta) l^2 q^2 + M^2 (l^2 dp^2 - a^2) = 0, so
// l = M a / sqrt((1 + 2 beta) q^2 + M^2 dp^2); l > 0 keeps X on the trial's side of the centre.
double shear_hardening_pressure(double p, double q, double p0, const NaccParams& m) {
  const double pc = 0.5 * (1.0 - m.beta) * p0, a = 0.5 * (1.0 + m.beta) * p0, dp = p - pc;
  const double M2 = m.friction * m.friction;
  const double l = m.friction * a / std::sqrt((1.0 + 2.0 * m.beta) * q * q + M2 * dp * dp);
  return pc + l * dp;
}

// Scale of y near the ellipse, for relative residuals: M^2 a^2 is y at the centre.
double yield_scale(double p0, const NaccParams& m) {
  const double a = 0.5 * (1.0 + m.beta) * p0;
  return m.friction * m.friction * a * a;
}

}  // namespace

Vector2d nacc_invariants(const Vector3d& s, double mu, double kappa) {
  const double J = s.prod();
  return {pressure(J, kappa), shear_invariant(deviator(s, mu, J))};
}

double nacc_yield(double p, double q, double p0, const NaccParams& m) {
  return q * q * (1.0 + 2.0 * m.beta) + m.friction * m.friction * (p + m.beta * p0) * (p - p0);
}

double nacc_damage(double alpha, double kappa, const NaccParams& m) {
  const double initial = nacc_p0(m.alpha0, kappa, m);
  return initial > 0 ? std::clamp(1.0 - nacc_p0(alpha, kappa, m) / initial, 0.0, 1.0) : 1.0;
}

NaccState nacc_return(const Vector3d& trial, double alpha, double mu, double kappa, const NaccParams& m) {
  NaccState out{trial, alpha, NaccCase::Elastic, 0};
  const double J = trial.prod();
  const double p0 = nacc_p0(alpha, kappa, m);
  const double p = pressure(J, kappa);
  const Vector3d s = deviator(trial, mu, J);
  const double q = shear_invariant(s);
  if (nacc_yield(p, q, p0, m) <= 0) return out;
  if (p > p0 || p < -m.beta * p0) {
    // Cases 1 and 2: the tip, an isotropic stretch at the tip's volume.
    out.branch = p > p0 ? NaccCase::Compression : NaccCase::Tension;
    const double Jn = volume_at_pressure(p > p0 ? p0 : -m.beta * p0, kappa);
    out.stretch.setConstant(std::cbrt(Jn));
    if (m.hardening) out.alpha += std::log(J / Jn);
    return out;
  }
  // Case 3: Eq. 14 at the trial pressure gives q; the deviator keeps its direction.
  out.branch = NaccCase::Shear;
  const double q2 = -m.friction * m.friction * (p + m.beta * p0) * (p - p0) / (1.0 + 2.0 * m.beta);
  const double ratio = std::sqrt(std::max(q2, 0.0)) / q;
  const double c = std::cbrt(J);
  const Vector3d d = (ratio * c * c / mu) * s;  // dev(b^E) of the returned state
  const double t = isotropic_part(d, J * J);
  out.stretch = (d.array() + t).sqrt().matrix();
  if (m.hardening) out.alpha += std::log(J / volume_at_pressure(shear_hardening_pressure(p, q, p0, m), kappa));
  return out;
}

namespace {

// Newton on J for p(J) = target, from the trial volume (the function is concave in J: no overshoot
// past the root from above, and from below the first step lands above it).
double newton_volume(double J, double target, double kappa, int& iterations) {
  for (int it = 0; it < 60; ++it) {
    const double f = pressure(J, kappa) - target, df = -kappa * J;
    const double step = f / df;
    J -= step;
    ++iterations;
    if (std::abs(step) <= 1e-15 * J) break;
  }
  return J;
}

// Newton on the ray parameter l of the case 3 hardening, from l = 1 (the trial state, outside).
double newton_shear_hardening(double p, double q, double p0, const NaccParams& m, int& iterations) {
  const double pc = 0.5 * (1.0 - m.beta) * p0, dp = p - pc;
  double l = 1.0;
  for (int it = 0; it < 60; ++it) {
    const double px = pc + l * dp, qx = l * q;
    const double f = nacc_yield(px, qx, p0, m);
    const double df = 2.0 * (1.0 + 2.0 * m.beta) * qx * q + m.friction * m.friction * (2.0 * px + (m.beta - 1.0) * p0) * dp;
    const double step = f / df;
    l -= step;
    ++iterations;
    if (std::abs(step) <= 1e-15 * std::abs(l)) break;
  }
  return pc + l * dp;
}

// Residual of case 3 in the unknowns x = (log stretches e, shear scale k):
//   r0, r1 = (s(e) - k s_tr)_{0,1} / mu   (the third follows: both deviators are trace free)
//   r2     = sum e - sum e_tr                (volume kept)
//   r3     = y(p(e), q(e)) / scale           (on the ellipse)
struct ShearSystem {
  Vector3d e_trial, s_trial;
  double mu, kappa, p0, scale;
  const NaccParams* m;

  Eigen::Vector4d residual(const Eigen::Vector4d& x, Eigen::Matrix4d* jac) const {
    const Vector3d e = x.head<3>();
    const Vector3d st = e.array().exp().matrix();
    const double J = std::exp(e.sum());
    const Vector3d s = deviator(st, mu, J);
    const double p = pressure(J, kappa), q2 = 1.5 * s.squaredNorm();
    const NaccParams& mp = *m;
    Eigen::Vector4d r;
    r[0] = (s[0] - x[3] * s_trial[0]) / mu;
    r[1] = (s[1] - x[3] * s_trial[1]) / mu;
    r[2] = e.sum() - e_trial.sum();
    r[3] = (q2 * (1.0 + 2.0 * mp.beta) + mp.friction * mp.friction * (p + mp.beta * p0) * (p - p0)) / scale;
    if (jac) {
      const Vector3d b = st.cwiseProduct(st);
      const double c = std::cbrt(J), g = mu / (c * c);
      Eigen::Matrix3d ds;  // ds_i / de_j
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) ds(i, j) = g * (2.0 * b[i] * (i == j) - 2.0 * b[j] / 3.0) - 2.0 * s[i] / 3.0;
      const double dp = -kappa * J * J;  // dp / de_j, the same for every j
      const Eigen::RowVector3d dq2 = 3.0 * s.transpose() * ds;
      const double dy_dp = mp.friction * mp.friction * (2.0 * p + (mp.beta - 1.0) * p0);
      jac->setZero();
      jac->block<2, 3>(0, 0) = ds.topRows<2>() / mu;
      (*jac)(0, 3) = -s_trial[0] / mu;
      (*jac)(1, 3) = -s_trial[1] / mu;
      jac->block<1, 3>(2, 0).setOnes();
      jac->block<1, 3>(3, 0) = ((1.0 + 2.0 * mp.beta) * dq2.array() + dy_dp * dp).matrix() / scale;
    }
    return r;
  }
};

}  // namespace

NaccState nacc_return_newton(const Vector3d& trial, double alpha, double mu, double kappa, const NaccParams& m) {
  NaccState out{trial, alpha, NaccCase::Elastic, 0};
  const double J = trial.prod();
  const double p0 = nacc_p0(alpha, kappa, m);
  const double p = pressure(J, kappa);
  const Vector3d s = deviator(trial, mu, J);
  const double q = shear_invariant(s);
  if (nacc_yield(p, q, p0, m) <= 0) return out;
  if (p > p0 || p < -m.beta * p0) {
    out.branch = p > p0 ? NaccCase::Compression : NaccCase::Tension;
    const double Jn = newton_volume(J, p > p0 ? p0 : -m.beta * p0, kappa, out.iterations);
    out.stretch.setConstant(std::cbrt(Jn));
    if (m.hardening) out.alpha += std::log(J / Jn);
    return out;
  }
  out.branch = NaccCase::Shear;
  const ShearSystem sys{trial.array().log().matrix(), s, mu, kappa, p0, std::max(yield_scale(p0, m), 1e-300), &m};
  Eigen::Vector4d x;
  x << sys.e_trial, 1.0;
  Eigen::Matrix4d jac;
  Eigen::Vector4d r = sys.residual(x, &jac);
  for (int it = 0; it < 60; ++it) {
    const Eigen::Vector4d dx = jac.partialPivLu().solve(-r);
    // Backtracking: halve the step until the residual falls.
    double step = 1.0;
    Eigen::Vector4d xn = x + dx, rn = sys.residual(xn, nullptr);
    while (rn.norm() > r.norm() && step > 1e-4) {
      step *= 0.5;
      xn = x + step * dx;
      rn = sys.residual(xn, nullptr);
    }
    x = xn;
    r = sys.residual(x, &jac);
    ++out.iterations;
    if (step * dx.head<3>().lpNorm<Eigen::Infinity>() <= 1e-15 || r.norm() <= 1e-15) break;
  }
  out.stretch = x.head<3>().array().exp().matrix();
  if (m.hardening) {
    const double px = newton_shear_hardening(p, q, p0, m, out.iterations);
    out.alpha += std::log(J / volume_at_pressure(px, kappa));
  }
  return out;
}

NaccCase nacc_project(Eigen::Matrix3d& F, double& alpha, double mu, double kappa, const NaccParams& m, NaccSolve solve) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const NaccState st = solve == NaccSolve::Analytic ? nacc_return(svd.singularValues(), alpha, mu, kappa, m)
                                                    : nacc_return_newton(svd.singularValues(), alpha, mu, kappa, m);
  if (st.branch == NaccCase::Elastic) return st.branch;
  // det F > 0 makes det U = det V, so U diag(s) V^T is F whatever their signs.
  F = svd.matrixU() * st.stretch.asDiagonal() * svd.matrixV().transpose();
  alpha = st.alpha;
  return st.branch;
}

}  // namespace shellfrac::brittle
