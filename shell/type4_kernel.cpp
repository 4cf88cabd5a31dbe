#include "shell/type4_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <vector>


namespace shellfrac::shell {

namespace {

// True when the Rankine criterion certainly gives c = 0, decided without the principal split (the
// scalar twin of the lane kernel's pre-check, type4_batch_impl.hpp): the largest principal value of tau is
// at most its Frobenius norm, which is at most B = |t11| c11 + |t12| (c11 + c22) + |t22| c22. With B and
// tau33 below sigma_f det F by a relative margin of 1e-6 (far above the round-off of the principal value),
// the full path's effective stress is <= sigma_f and rankine_damage returns 0. NaN anywhere: false.
bool surely_below_failure(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2, double normal, double sigma_f,
                          double detF) {
  const double c11 = g1.squaredNorm(), c22 = g2.squaredNorm();
  const double B = std::abs(tau.t11) * c11 + std::abs(tau.t12) * (c11 + c22) + std::abs(tau.t22) * c22;
  const double limit = 0.999999 * sigma_f * detF;
  return sigma_f > 0.0 && detF > 0.0 && B <= limit && normal <= limit && B < HUGE_VAL && limit < HUGE_VAL;
}

}  // namespace

InPlaneTensor type4_damaged_stress(const Type4Data& d, const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2,
                                   double detF, size_t q, size_t ql, const double* tau33) {
  // Effective stress: the largest principal Cauchy stress of the undamaged trial state (thesis sec.
  // 4.4.1). The in-plane stress has a zero transverse principal value, so it is at least 0; plane strain
  // has tau^33 there instead (g_3 = a_3 is a unit principal direction).
  const double normal = tau33 ? *tau33 : 0.0;
  double c = 0.0;
  if (!surely_below_failure(tau, g1, g2, normal, d.failure_stress[q], detF)) {
    const double effective = std::max(normal, largest_principal(tau, g1, g2)) / detF;
    c = rankine_damage(effective, d.failure_stress[q], d.brittleness[q]);  // thesis Eq. 2.28
  }
  if (d.monotone) c = std::max(c, d.damage[ql]);  // conventional rule, kept for comparison
  d.damage[ql] = c;                               // healing rule: c^{n+1} = cbar
  d.damage_history[ql] = std::max(d.damage_history[ql], c);
  // thesis Eq. 2.29-2.31, with the residual share r kept by a fully damaged point (FractureParams)
  return c > 0 ? weaken_tensile_part(tau, g1, g2, (1.0 - d.residual) * c) : tau;
}

Type4Status type4_point_force(const Type4Data& d, size_t q, const Type4Basis& b, bool membrane, double r33,
                              Vec3* force) {
  const size_t L = static_cast<size_t>(d.layers);
  // MLS supports can hold more control points than a NURBS one (up to the chain's largest factor):
  // those take their pointer list from the heap.
  const Vec3* fixed[kType4MaxSupport];
  std::vector<const Vec3*> large;
  const Vec3** pts = fixed;
  if (b.n > kType4MaxSupport) {
    large.resize(static_cast<size_t>(b.n));
    pts = large.data();
  }
  for (int s = 0; s < b.n; ++s) pts[s] = &d.x[static_cast<size_t>(b.index[s])];
  const SurfaceJet jet = surface_jet(pts, b.basis + 1, b.n, 6);
  NormalJet nj;
  if (!normal_jet(jet, nj)) return kType4Degenerate;
  // dPsi/dg_alpha summed over layers (K) and weighted by xi3 (C); the KL in-plane stress has no
  // g_3 component, so dPsi/dg_3 = 0 (thesis Eq. 4.14).
  Vec3 K1 = Vec3::Zero(), K2 = Vec3::Zero(), C1 = Vec3::Zero(), C2 = Vec3::Zero();
  for (size_t l = 0; l < L; ++l) {
    // The 2D mid-surface model sees the mid-surface metric at every layer (no bending); so does a
    // membrane-only point, against the mid-surface rest metric (its own layer's when plastic).
    const bool flat = membrane || d.mid_surface;
    const double xi3 = flat ? 0.0 : d.xi3[l];
    const ReferenceLayer& ref = d.ref[q * L + (d.mid_surface || (membrane && !d.plastic) ? L / 2 : l)];
    const Vec3 g1 = jet.a1 + xi3 * nj.dn1, g2 = jet.a2 + xi3 * nj.dn2;
    // Plastic materials: return-map the current (trial) state first; it needs the same kinematics.
    if (d.plastic) von_mises_return(g1, g2, d.mu, d.lambda, d.plasticity, d.ref[q * L + l], d.plastic_strain[q * L + l]);
    const InPlaneStress st = neo_hookean_in_plane(g1, g2, ref, d.mu, d.lambda, d.model, r33);
    if (!st.ok) return kType4Degenerate;
    if (st.J > kRunawayAreaRatio) return kType4Runaway;  // no sheet survives this intact: the step diverged
    InPlaneTensor tau{st.t11, st.t12, st.t22};
    // Plane strain keeps the transverse normal stress tau^33 = lambda ln J on g_3 = a_3. It does no
    // work (dPsi/dg_3 is parallel to the unit normal, whose variations are normal to it), so it
    // matters only as a principal stress of the damage criterion.
    const double tau33 = d.plane_strain ? d.lambda * std::log(st.J) : 0.0;
    if (d.fracturing) tau = type4_damaged_stress(d, tau, g1, g2, st.J * st.lambda3, q, q * L + l, d.plane_strain ? &tau33 : nullptr);
    // dPsi/dg_alpha = V tau^{alpha beta} g_beta (P~ : dF = tau^{ab} g_b . dg_a)
    const double V = d.volume[q * L + l];
    const Vec3 k1 = V * (tau.t11 * g1 + tau.t12 * g2);
    const Vec3 k2 = V * (tau.t12 * g1 + tau.t22 * g2);
    K1 += k1;
    K2 += k2;
    C1 += xi3 * k1;
    C2 += xi3 * k2;
  }
  const JetGradient gr = kl_basis_adjoint(jet, nj, K1, K2, C1, C2, Vec3::Zero());
  for (int s = 0; s < b.n; ++s) {
    const double* ds = b.basis + s * 6;
    force[s] -= ds[1] * gr.a1 + ds[2] * gr.a2 + ds[3] * gr.a11 + ds[4] * gr.a12 + ds[5] * gr.a22;
  }
  return kType4Ok;
}

namespace detail {

bool type4_return_map_lane(const Type4Data& d, const double g1[3], const double g2[3], size_t ql) {
  return von_mises_return(Vec3(g1[0], g1[1], g1[2]), Vec3(g2[0], g2[1], g2[2]), d.mu, d.lambda, d.plasticity, d.ref[ql],
                          d.plastic_strain[ql]);
}

}  // namespace detail

namespace {

using BatchFunction = void (*)(const Type4Data&, const Type4Batch&, Type4BatchResult&);

bool cpu_has_avx2_fma() {
#if defined(SHELLFRAC_TYPE4_AVX2)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

bool cpu_has_avx512() {
#if defined(SHELLFRAC_TYPE4_AVX2)
  __builtin_cpu_init();
  return cpu_has_avx2_fma() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512dq");
#else
  return false;
#endif
}

BatchFunction pick_batch_function() {
#if defined(SHELLFRAC_TYPE4_AVX2)
  if (cpu_has_avx512()) return detail::type4_force_batch_avx512;
  if (cpu_has_avx2_fma()) return detail::type4_force_batch_avx2;
#endif
  return detail::type4_force_batch_generic;
}

const BatchFunction kBatchFunction = pick_batch_function();

}  // namespace

void type4_force_batch(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out) { kBatchFunction(d, batch, out); }

const char* type4_batch_isa() { return cpu_has_avx512() ? "avx512" : cpu_has_avx2_fma() ? "avx2-fma" : "generic"; }

}  // namespace shellfrac::shell
