#include "shell/damage.hpp"

#include <algorithm>
#include <cmath>

namespace shellfrac::shell {

double brittleness(double failure_stress, double fracture_energy, double youngs_modulus, double characteristic_length) {
  const double hbar = failure_stress * failure_stress / (2.0 * youngs_modulus * fracture_energy);
  const double hl = hbar * characteristic_length;
  if (!(hl < 1.0) || !(hl > 0.0)) return -1.0;
  return hl / (1.0 - hl);
}

double rankine_damage(double effective_stress, double failure_stress, double brittleness) {
  if (!(effective_stress > failure_stress)) return 0.0;
  if (effective_stress >= failure_stress * (1.0 + 1.0 / brittleness)) return 1.0;
  return std::min(1.0, (1.0 + brittleness) * (1.0 - failure_stress / effective_stress));
}

namespace {

// The in-plane stress in the orthonormal frame e_1 = g_1/|g_1|, e_2 in span(g_1, g_2):
// sigma_ij = e_i . tau . e_j = (E T E^T)_ij with E_ia = e_i . g_a upper triangular.
struct TangentFrame {
  double e11, e12, e22;  // E = [[e11, e12], [0, e22]]
};

TangentFrame frame(const Vec3& g1, const Vec3& g2) {
  const double n1 = g1.norm();
  const double e12 = g1.dot(g2) / n1;
  const double e22 = std::sqrt(std::max(0.0, g2.squaredNorm() - e12 * e12));
  return {n1, e12, e22};
}

// Local symmetric components s = E T E^T.
void to_local(const InPlaneTensor& t, const TangentFrame& f, double& s11, double& s12, double& s22) {
  // E T: rows (e11 t1a + e12 t2a, e22 t2a)
  const double a11 = f.e11 * t.t11 + f.e12 * t.t12, a12 = f.e11 * t.t12 + f.e12 * t.t22;
  const double a21 = f.e22 * t.t12, a22 = f.e22 * t.t22;
  s11 = a11 * f.e11 + a12 * f.e12;
  s12 = a12 * f.e22;
  s22 = a22 * f.e22;
  (void)a21;
}

void eigen_sym2(double s11, double s12, double s22, double& l1, double& l2, double& c, double& s) {
  // Principal values l1 >= l2 and the unit eigenvector (c, s) of l1. No trigonometry: this runs for
  // every damaged layer point every step.
  const double m = 0.5 * (s11 + s22), d = 0.5 * (s11 - s22);
  const double r = std::sqrt(d * d + s12 * s12);
  l1 = m + r;
  l2 = m - r;
  if (r <= 1e-300) {
    c = 1.0;
    s = 0.0;
    return;
  }
  // (A - l1 I) v = 0: v = (s12, l1 - s11) or (l1 - s22, s12); take the better conditioned one.
  double vx = s12, vy = l1 - s11;
  if (d > 0) {
    vx = l1 - s22;
    vy = s12;
  }
  const double n = std::sqrt(vx * vx + vy * vy);
  c = vx / n;
  s = vy / n;
}

}  // namespace

double largest_principal(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2) {
  double s11, s12, s22;
  to_local(tau, frame(g1, g2), s11, s12, s22);
  const double d = 0.5 * (s11 - s22);
  return 0.5 * (s11 + s22) + std::sqrt(d * d + s12 * s12);
}

InPlaneTensor weaken_tensile_part(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2, double damage) {
  if (damage <= 0.0) return tau;
  const TangentFrame f = frame(g1, g2);
  double s11, s12, s22, l1, l2, c, s;
  to_local(tau, f, s11, s12, s22);
  eigen_sym2(s11, s12, s22, l1, l2, c, s);
  // thesis Eq. 2.30: only positive principal values are scaled
  if (l1 > 0) l1 *= 1.0 - damage;
  if (l2 > 0) l2 *= 1.0 - damage;
  // thesis Eq. 2.31: reassemble sum sigma_i q_i (x) q_i in the local frame
  const double w11 = l1 * c * c + l2 * s * s;
  const double w12 = (l1 - l2) * c * s;
  const double w22 = l1 * s * s + l2 * c * c;
  // back to contravariant components: T = E^-1 W E^-T with E upper triangular
  const double i11 = 1.0 / f.e11, i22 = 1.0 / f.e22, i12 = -f.e12 / (f.e11 * f.e22);
  // E^-1 W: rows (i11 w1b + i12 w2b, i22 w2b)
  const double b11 = i11 * w11 + i12 * w12, b12 = i11 * w12 + i12 * w22;
  const double b21 = i22 * w12, b22 = i22 * w22;
  InPlaneTensor out;
  out.t11 = b11 * i11 + b12 * i12;
  out.t12 = b12 * i22;
  out.t22 = b22 * i22;
  (void)b21;
  return out;
}

}  // namespace shellfrac::shell
