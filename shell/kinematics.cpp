#include "shell/kinematics.hpp"

#include <Eigen/Geometry>

namespace shellfrac::shell {

SurfaceJet surface_jet(const Vec3* const* points, const double* d, int n, int stride) {
  SurfaceJet s{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  for (int i = 0; i < n; ++i) {
    const Vec3& x = *points[i];
    const double* r = d + stride * i;
    s.a1 += r[0] * x;
    s.a2 += r[1] * x;
    s.a11 += r[2] * x;
    s.a12 += r[3] * x;
    s.a22 += r[4] * x;
  }
  return s;
}

bool normal_jet(const SurfaceJet& s, NormalJet& j) {
  const Vec3 v = s.a1.cross(s.a2);
  const double L = v.norm();
  if (!(L > 1e-300)) return false;
  j.length = L;
  j.n = v / L;
  j.dv1 = s.a11.cross(s.a2) + s.a1.cross(s.a12);
  j.dv2 = s.a12.cross(s.a2) + s.a1.cross(s.a22);
  // d(v/|v|) = (I - n n^T) dv / |v|
  j.dn1 = (j.dv1 - j.n * j.n.dot(j.dv1)) / L;
  j.dn2 = (j.dv2 - j.n * j.n.dot(j.dv2)) / L;
  return true;
}

Mat3 kl_basis(const SurfaceJet& s, const NormalJet& j, double xi3) {
  Mat3 G;
  G.col(0) = s.a1 + xi3 * j.dn1;
  G.col(1) = s.a2 + xi3 * j.dn2;
  G.col(2) = j.n;
  return G;
}

JetGradient kl_basis_adjoint(const SurfaceJet& s, const NormalJet& j, const Vec3& K1, const Vec3& K2,
                             const Vec3& C1, const Vec3& C2, const Vec3& K3) {
  const Vec3& n = j.n;
  const double inv_L = 1.0 / j.length;
  auto project = [&](const Vec3& c) { return Vec3((c - n * n.dot(c)) * inv_L); };  // (I - n n^T) c / L

  // E = K_a . a_a + C_a . a_3,a + K3 . a_3 with a_3 = n(v), a_3,a = (I - n n^T) v_a / |v|,
  // v = a1 x a2, v_a = d v / d xi_a.
  const Vec3 g_dv1 = project(C1);  // dE/dv_1
  const Vec3 g_dv2 = project(C2);  // dE/dv_2
  // dE/dv: through n in K3 . n, and through n and |v| in each a_3,a.
  Vec3 g_v = project(K3);
  const Vec3 pv1 = project(j.dv1), pv2 = project(j.dv2);
  g_v -= inv_L * (n.dot(j.dv1) * g_dv1 + C1.dot(n) * pv1 + C1.dot(j.dn1) * n);
  g_v -= inv_L * (n.dot(j.dv2) * g_dv2 + C2.dot(n) * pv2 + C2.dot(j.dn2) * n);

  JetGradient g;
  // v = a1 x a2
  g.a1 = K1 + s.a2.cross(g_v);
  g.a2 = K2 + g_v.cross(s.a1);
  // v_1 = a11 x a2 + a1 x a12
  g.a11 = s.a2.cross(g_dv1);
  g.a2 += g_dv1.cross(s.a11);
  g.a1 += s.a12.cross(g_dv1);
  g.a12 = g_dv1.cross(s.a1);
  // v_2 = a12 x a2 + a1 x a22
  g.a12 += s.a2.cross(g_dv2);
  g.a2 += g_dv2.cross(s.a12);
  g.a1 += s.a22.cross(g_dv2);
  g.a22 = g_dv2.cross(s.a1);
  return g;
}

}  // namespace shellfrac::shell
