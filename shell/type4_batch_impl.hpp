// The batched Type IV force kernel: eight NURBS quadrature points per call, one per lane, every
// per-point formula of type4_point_force (shell/type4_kernel.cpp) written on lanes. Included by
// type4_batch_generic.cpp and type4_batch_avx2.cpp, each inside an anonymous namespace and compiled with
// its own instruction set; defines the file-local entry point `batch_kernel`.
//
// Differences from the scalar reference are round-off only: ln and e^x are the lane versions of
// simd_lanes.hpp (a few ulp), products may be fused, the condensed fibre stretch iterates on its logarithm
// (lane_log_fibre_stretches), and the von Mises return runs the scalar code for the lanes whose trial stress
// is within 1e-8 of the yield surface or beyond it.

#include "shell/simd_lanes.hpp"

// Lane l of a Lanes3 as a plain array.
SF_INLINE void lane_of(const Lanes3& v, int l, double out[3]) {
  out[0] = v.x[l];
  out[1] = v.y[l];
  out[2] = v.z[l];
}

// Metric invariants and the in-plane Neo-Hookean Kirchhoff stress of one layer (neo_hookean_in_plane).
struct LaneStress {
  Lanes t11, t12, t22;
  Lanes J;
  Lanes lnJ;         // ln J (of J where ok, of 1 elsewhere)
  Lanes ln_lambda3;  // ln of the fibre stretch (its value is needed only by the damage criterion)
  // lambda_3^2 to within 3e-8 relative without a further e^x, NaN where not known (a lane the Newton loop
  // did not settle, a non-positive given stretch): enough for the damage pre-check (lane_surely_intact).
  Lanes lambda3_sq;
  LaneMask ok;
};

// Condensed fibre stretch (condensed_fibre_stretch) of each of the L layers of a point: the same root of
// mu (l^2 - 1) + lambda ln(J l) = 0, found by Newton on s = ln l instead of l, h(s) = mu (e^{2s} - 1) +
// lambda (s + ln J), which is convex and increasing: one e^x and one division per iteration instead of a
// logarithm and two divisions, and ln(J l) = ln J + s for the pressure needs no further logarithm. Start:
// the root's expansion to second order in x = ln J, s = a x + b x^2 with a = -lambda/(2 mu + lambda),
// b = -2 mu a^2/(2 mu + lambda). A lane stops after the step that moved it by at most 1e-8: the Newton error
// is then below (h''/2h') 1e-16 <= 1e-16 (h''/2h' = 2 mu e^{2s}/(2 mu e^{2s} + lambda) <= 1), the scalar
// loop's 1e-15 relative. Writes s = ln l3 per layer, and l3_sq: the layer's last iteration's e^{2s}, which
// is l3^2 to within |2 step| <= 2e-8 for a lane that settled in it and to the ulp for one that settled
// earlier (its s no longer moved); NaN for a lane that never settled.
//
// The layers' Newton chains are independent, so one pass over the layers per iteration lets the core
// overlap them, where a layer alone waits on its e^x and division. A layer stops iterating when all its
// lanes are done, as it would in a loop of its own, so its results do not depend on the other layers.
struct LaneNewton {
  Lanes s, e2s;
  LaneMask done;
  bool settled = false;  // every lane done: this layer takes no further iteration
};
template <size_t L>
SF_INLINE void lane_log_fibre_stretches(const Lanes* lnJ, double mu, double lambda, Lanes* s_out, Lanes* l3_sq) {
  const double a = -lambda / (2.0 * mu + lambda), b = -2.0 * mu * a * a / (2.0 * mu + lambda);
  LaneNewton n[L];
  for (size_t l = 0; l < L; ++l) {
    n[l].s = lnJ[l] * (a + b * lnJ[l]);
    n[l].done = splat_int(0);
  }
  for (int it = 0; it < 30; ++it) {
    bool all_settled = true;
    for (size_t l = 0; l < L; ++l) {
      LaneNewton& w = n[l];
      if (w.settled) continue;
      w.e2s = vexp(2.0 * w.s);
      const Lanes h = mu * (w.e2s - 1.0) + lambda * (w.s + lnJ[l]);
      const Lanes step = h / ((2.0 * mu) * w.e2s + lambda);
      w.s = select(w.done, w.s, w.s - step);
      w.done = w.done | (vabs(step) <= 1e-8);
      w.settled = all(w.done);
      all_settled = all_settled && w.settled;
    }
    if (all_settled) break;
  }
  for (size_t l = 0; l < L; ++l) {
    s_out[l] = n[l].s;
    l3_sq[l] = select(n[l].done, n[l].e2s, splat(__builtin_nan("")));
  }
}

// The same for a layer count known only at run time (the layer rules have 1 or 3; the batched kernel takes up
// to kType4MaxLayers): a fixed count lets the compiler keep every layer's Newton state in registers.
SF_INLINE void lane_log_fibre_stretches(const Lanes* lnJ, size_t L, double mu, double lambda, Lanes* s_out,
                                        Lanes* l3_sq) {
  switch (L) {
    case 1: return lane_log_fibre_stretches<1>(lnJ, mu, lambda, s_out, l3_sq);
    case 2: return lane_log_fibre_stretches<2>(lnJ, mu, lambda, s_out, l3_sq);
    case 3: return lane_log_fibre_stretches<3>(lnJ, mu, lambda, s_out, l3_sq);
    default: return lane_log_fibre_stretches<shellfrac::shell::kType4MaxLayers>(lnJ, mu, lambda, s_out, l3_sq);
  }
}

// The metric part of the in-plane stress, before the fibre stretch: the deformed metric's inverse, J and
// ln J. ref: g11, g12, g22 of the rest metric and 1 / sqrt of its determinant.
struct LaneMetric {
  Lanes i11, i12, i22;  // deformed g^{ab}
  Lanes J, Jsafe, lnJ;
  LaneMask ok;
};
SF_INLINE LaneMetric lane_metric(const Lanes3& g1, const Lanes3& g2, const Lanes ref[4]) {
  LaneMetric m;
  const Lanes c11 = dot(g1, g1), c12 = dot(g1, g2), c22 = dot(g2, g2);
  const Lanes det = c11 * c22 - c12 * c12;
  m.J = vsqrt(det) * ref[3];  // ref[3]: 1 / sqrt(det of the rest metric), stored inverted
  // det > 0, J > 0 and finite (the scalar checks); NaN fails every comparison.
  m.ok = (det > 0.0) & (m.J > 0.0) & (m.J < __builtin_inf());
  m.Jsafe = select(m.ok, m.J, splat(1.0));  // keep masked lanes finite in the iterations
  const Lanes inv = 1.0 / det;
  m.i11 = c22 * inv;
  m.i12 = -c12 * inv;
  m.i22 = c11 * inv;
  m.lnJ = vlog(m.Jsafe);
  return m;
}

// The in-plane Neo-Hookean Kirchhoff stress from the metric part and, for the condensed model, the fibre
// stretch's logarithm ln_l3 and square l3_sq (lane_log_fibre_stretches).
SF_INLINE LaneStress lane_stress_of(const LaneMetric& m, const Lanes ref[4], double mu, double lambda,
                                    shellfrac::shell::TransverseModel model, Lanes given, Lanes ln_l3, Lanes l3_sq) {
  using shellfrac::shell::TransverseModel;
  LaneStress s;
  s.J = m.J;
  s.ok = m.ok;
  s.lnJ = m.lnJ;
  Lanes ln_detF;  // ln(J lambda_3)
  switch (model) {
    case TransverseModel::Condensed:
      s.ln_lambda3 = ln_l3;
      s.lambda3_sq = l3_sq;
      ln_detF = m.lnJ + ln_l3;
      break;
    case TransverseModel::Given:
      s.ln_lambda3 = splat(0.0);  // unused: the damage criterion takes `given` itself
      s.lambda3_sq = select(given > 0.0, given * given, splat(__builtin_nan("")));
      ln_detF = vlog(m.Jsafe * given);
      break;
    case TransverseModel::Rigid:
      s.ln_lambda3 = splat(0.0);
      s.lambda3_sq = splat(1.0);
      ln_detF = m.lnJ;
      break;
  }
  const Lanes p = lambda * ln_detF;
  s.t11 = mu * (ref[0] - m.i11) + p * m.i11;
  s.t12 = mu * (ref[1] - m.i12) + p * m.i12;
  s.t22 = mu * (ref[2] - m.i22) + p * m.i22;
  return s;
}

// Metric invariants and the in-plane Neo-Hookean Kirchhoff stress of one layer (neo_hookean_in_plane).
SF_INLINE LaneStress lane_in_plane_stress(const Lanes3& g1, const Lanes3& g2, const Lanes ref[4], double mu,
                                          double lambda, shellfrac::shell::TransverseModel model, Lanes given) {
  const LaneMetric m = lane_metric(g1, g2, ref);
  Lanes ln_l3 = splat(0.0), l3_sq = splat(0.0);
  if (model == shellfrac::shell::TransverseModel::Condensed) lane_log_fibre_stretches(&m.lnJ, 1, mu, lambda, &ln_l3, &l3_sq);
  return lane_stress_of(m, ref, mu, lambda, model, given, ln_l3, l3_sq);
}

// Orthonormal in-plane frame e_1 = g_1/|g_1| (damage.cpp): E = [[e11, e12], [0, e22]].
struct LaneFrame {
  Lanes e11, e12, e22;
};
SF_INLINE LaneFrame lane_frame(const Lanes3& g1, const Lanes3& g2) {
  LaneFrame f;
  f.e11 = vsqrt(dot(g1, g1));
  f.e12 = dot(g1, g2) / f.e11;
  f.e22 = vsqrt(vmax(splat(0.0), dot(g2, g2) - f.e12 * f.e12));
  return f;
}

// Lanes whose damage is certainly 0 this step, decided without the principal split: Rankine (thesis Eq.
// 2.28) gives c = 0 when max(tau_33, largest principal of tau) / det F <= sigma_f, and the largest principal
// value is at most the Frobenius norm of tau = tau^{ab} g_a (x) g_b, which is at most
// B = |t11| c11 + |t12| (c11 + c22) + |t22| c22 (|g_1| |g_2| <= (c11 + c22)/2). With B and tau_33 below
// sigma_f det F by a relative margin of 1e-6 (far above the round-off of either computation and the 3e-8 of
// lambda3_sq), lane_damage would compute c = 0 and leave tau unchanged; compared squared, so det F needs no
// e^x. A lane with stored damage under the monotone rule is never certain. NaN anywhere: not certain.
// `always` holds the lanes' layer-independent conditions, sigma_f > 0 and c_old <= 0 (the caller forms it
// once per group); without plane strain, normal = 0 passes and its test is skipped.
SF_INLINE LaneMask lane_surely_intact(const LaneStress& st, const Lanes3& g1, const Lanes3& g2, bool plane_strain,
                                      Lanes normal, Lanes sigma_f, LaneMask always) {
  const Lanes c11 = dot(g1, g1), c22 = dot(g2, g2);
  const Lanes B = vabs(st.t11) * c11 + vabs(st.t12) * (c11 + c22) + vabs(st.t22) * c22;
  const Lanes limit_sq = 0.999996 * (sigma_f * st.J) * (sigma_f * st.J) * st.lambda3_sq;  // (sigma_f det F)^2
  const Lanes B_sq = B * B;
  const double inf = __builtin_inf();  // an overflowed square would pass any limit
  const LaneMask intact = always & st.ok & (B_sq <= limit_sq) & (B_sq < inf);
  if (!plane_strain) return intact;
  const Lanes normal_sq = normal * normal;
  return intact & ((normal <= 0.0) | ((normal_sq <= limit_sq) & (normal_sq < inf)));
}

// Rankine damage (thesis Eq. 2.28) and tensile weakening (Eq. 2.29-2.31) on lanes; c_old: the stored damage
// (used by the monotone rule); returns c in `c_out`.
SF_INLINE void lane_damage(Lanes& t11, Lanes& t12, Lanes& t22, const Lanes3& g1, const Lanes3& g2, Lanes detF,
                           Lanes normal, Lanes sigma_f, Lanes H, Lanes c_old, bool monotone, double residual,
                           Lanes& c_out) {
  const LaneFrame f = lane_frame(g1, g2);
  // local components s = E T E^T
  const Lanes a11 = f.e11 * t11 + f.e12 * t12, a12 = f.e11 * t12 + f.e12 * t22, a22 = f.e22 * t22;
  const Lanes s11 = a11 * f.e11 + a12 * f.e12, s12 = a12 * f.e22, s22 = a22 * f.e22;
  const Lanes m = 0.5 * (s11 + s22), dd = 0.5 * (s11 - s22);
  const Lanes r = vsqrt(dd * dd + s12 * s12);
  const Lanes largest = m + r;
  const Lanes effective = vmax(normal, largest) / detF;
  // 0 below sigma_f (and for NaN), 1 beyond sigma_f (1 + 1/H), linear softening between.
  const Lanes soft = vmin(splat(1.0), (1.0 + H) * (1.0 - sigma_f / effective));
  Lanes c = select(effective >= sigma_f * (1.0 + 1.0 / H), splat(1.0), soft);
  c = select(effective > sigma_f, c, splat(0.0));
  if (monotone) c = vmax(c, c_old);
  c_out = c;
  const LaneMask damaged = c > 0.0;
  if (!any(damaged)) return;
  // principal values l1 >= l2 and the unit eigenvector (cs, sn) of l1
  Lanes l1 = largest, l2 = m - r;
  const LaneMask d_pos = dd > 0.0;
  const Lanes vx = select(d_pos, l1 - s22, s12), vy = select(d_pos, s12, l1 - s11);
  const Lanes nrm = vsqrt(vx * vx + vy * vy);
  const LaneMask round = r <= 1e-300;
  const Lanes cs = select(round, splat(1.0), vx / nrm), sn = select(round, splat(0.0), vy / nrm);
  const Lanes keep = 1.0 - (1.0 - residual) * c;  // 1 - c in the thesis (residual 0, FractureParams)
  l1 = select(l1 > 0.0, l1 * keep, l1);
  l2 = select(l2 > 0.0, l2 * keep, l2);
  const Lanes w11 = l1 * cs * cs + l2 * sn * sn;
  const Lanes w12 = (l1 - l2) * cs * sn;
  const Lanes w22 = l1 * sn * sn + l2 * cs * cs;
  const Lanes i11 = 1.0 / f.e11, i22 = 1.0 / f.e22, i12 = -f.e12 / (f.e11 * f.e22);
  const Lanes b11 = i11 * w11 + i12 * w12, b12 = i11 * w12 + i12 * w22, b22 = i22 * w22;
  t11 = select(damaged, b11 * i11 + b12 * i12, t11);
  t12 = select(damaged, b12 * i22, t12);
  t22 = select(damaged, b22 * i22, t22);
}

// The lanes' view of one group of the batch: lanes o .. o + kLanes - 1.
struct LaneGroup {
  const shellfrac::shell::Type4Data& d;
  const shellfrac::shell::Type4Batch& b;
  int o;
  const size_t* q;            // quadrature point per lane
  unsigned active;            // lane bits
  size_t L;                   // layers
  Lanes basis(int s, int k) const {  // R_s,k of support function s (k: 1, 2, 11, 12, 22)
    Lanes v;
    __builtin_memcpy(&v, b.basis + (s * 5 + k) * shellfrac::shell::kType4Lanes + o, sizeof(Lanes));
    return v;
  }
};

// Mid-surface jet a_alpha, x_,alpha beta (thesis Eq. 4.1) and the unit normal with its derivatives
// (normal_jet).
struct LaneJet {
  Lanes3 a1, a2, a11, a12, a22;
  Lanes3 nrm, dv1, dv2, dn1, dn2;
  Lanes inv_len;
  LaneMask degenerate;  // |a1 x a2| not above 1e-300
};

SF_INLINE LaneJet lane_jet(const LaneGroup& g) {
  using namespace shellfrac::shell;
  const int* const* sup = g.b.support + g.o;
  // Control point positions as raw doubles (Vec3 is three packed doubles): no Eigen code is instantiated
  // in this translation unit.
  const double* xs = reinterpret_cast<const double*>(g.d.x);
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
  LaneJet j;
  j.a1 = j.a2 = j.a11 = j.a12 = j.a22 = zero3();
  for (int s = 0; s < g.b.n; ++s) {  // sum over the support of basis x position
    Lanes3 X;
    if (g.b.shared_support) {
      const double* p = xs + 3 * static_cast<size_t>(sup[0][s]);
      X = {splat(p[0]), splat(p[1]), splat(p[2])};
    } else {
      const double* p[kLanes];
      for (int i = 0; i < kLanes; ++i) p[i] = xs + 3 * static_cast<size_t>(sup[i][s]);
      X = {gather([&](int i) { return p[i][0]; }), gather([&](int i) { return p[i][1]; }),
           gather([&](int i) { return p[i][2]; })};
    }
    j.a1 = j.a1 + g.basis(s, 0) * X;
    j.a2 = j.a2 + g.basis(s, 1) * X;
    j.a11 = j.a11 + g.basis(s, 2) * X;
    j.a12 = j.a12 + g.basis(s, 3) * X;
    j.a22 = j.a22 + g.basis(s, 4) * X;
  }
  const Lanes3 v = cross(j.a1, j.a2);
  const Lanes len = vsqrt(dot(v, v));
  j.degenerate = ~(len > 1e-300);
  j.inv_len = 1.0 / len;
  j.nrm = j.inv_len * v;
  j.dv1 = cross(j.a11, j.a2) + cross(j.a1, j.a12);
  j.dv2 = cross(j.a12, j.a2) + cross(j.a1, j.a22);
  j.dn1 = j.inv_len * (j.dv1 - dot(j.nrm, j.dv1) * j.nrm);
  j.dn2 = j.inv_len * (j.dv2 - dot(j.nrm, j.dv2) * j.nrm);
  return j;
}

// Rest metric of layer lref per lane: g11, g12, g22 and 1 / sqrt of its determinant.
SF_INLINE void lane_reference(const LaneGroup& g, size_t lref, Lanes ref[4]) {
  using namespace shellfrac::shell;
  if (g.b.ref_lanes) {  // lane order: plain loads
    for (int k = 0; k < 4; ++k) __builtin_memcpy(&ref[k], g.b.ref_lanes + (lref * 4 + k) * kType4Lanes + g.o, sizeof(Lanes));
    return;
  }
  const ReferenceLayer* rl[kLanes];
  for (int i = 0; i < kLanes; ++i) rl[i] = &g.d.ref[g.q[i] * g.L + lref];
  ref[0] = gather([&](int i) { return rl[i]->g11; });
  ref[1] = gather([&](int i) { return rl[i]->g12; });
  ref[2] = gather([&](int i) { return rl[i]->g22; });
  ref[3] = 1.0 / gather([&](int i) { return rl[i]->sqrt_det; });
}

// Elastic check of von_mises_return on lanes: q^2 = (t1 + t2)^2 - 3 t1 t2 from the invariants of the
// mixed tensor, with the condensed stress. Lanes within 1e-8 of the surface or past it run the scalar
// return mapping, which decides with its own arithmetic exactly as the reference does; their rest metric
// (ref) is reloaded and the stress recomputed.
SF_INLINE void lane_plastic_return(const LaneGroup& g, size_t l, size_t lref, const Lanes3& g1, const Lanes3& g2,
                                   const Lanes& given, LaneMask failed, Lanes ref[4], LaneStress& st) {
  using namespace shellfrac::shell;
  const Type4Data& d = g.d;
  const LaneStress sc = d.model == TransverseModel::Condensed
                            ? st
                            : lane_in_plane_stress(g1, g2, ref, d.mu, d.lambda, TransverseModel::Condensed, given);
  const Lanes c11 = dot(g1, g1), c12 = dot(g1, g2), c22 = dot(g2, g2);
  const Lanes trace = sc.t11 * c11 + 2.0 * sc.t12 * c12 + sc.t22 * c22;
  const Lanes det = (sc.t11 * sc.t22 - sc.t12 * sc.t12) * (c11 * c22 - c12 * c12);
  const Lanes alpha = gather([&](int i) { return d.plastic_strain[g.q[i] * g.L + l]; });
  const Lanes limit = d.plasticity.yield_stress + d.plasticity.hardening * alpha;
  const LaneMask near = sc.ok & ~failed & (trace * trace - 3.0 * det > (1.0 - 1e-8) * (limit * limit));
  if (!any(near)) return;
  bool yielded = false;
  for (int i = 0; i < kLanes; ++i) {
    if (!near[i] || !((g.active >> i) & 1u)) continue;
    double p1[3], p2[3];
    lane_of(g1, i, p1);
    lane_of(g2, i, p2);
    if (detail::type4_return_map_lane(d, p1, p2, g.q[i] * g.L + l)) {
      yielded = true;
      const ReferenceLayer& r = d.ref[g.q[i] * g.L + lref];
      ref[0].set(i, r.g11);
      ref[1].set(i, r.g12);
      ref[2].set(i, r.g22);
      ref[3].set(i, 1.0 / r.sqrt_det);
    }
  }
  if (yielded) st = lane_in_plane_stress(g1, g2, ref, d.mu, d.lambda, d.model, given);
}

// Writes the layers' damage and history back for the active lanes that did not fail.
SF_INLINE void lane_store_damage(const LaneGroup& g, const Lanes* c_new, LaneMask failed, LaneMask runaway,
                                 const int* status) {
  using namespace shellfrac::shell;
  // Intact material (every lane and layer +0, all lanes written, points consecutive): the lanes' damage
  // is one run of kLanes * L values to clear, and the history (never below +0) keeps its value.
  LaneMask nonzero = failed | runaway;
  for (size_t l = 0; l < g.L; ++l) nonzero = nonzero | as_mask(c_new[l]);
  bool consecutive = (g.active & ((1u << kLanes) - 1)) == (1u << kLanes) - 1;
  for (int i = 1; i < kLanes; ++i) consecutive = consecutive && g.q[i] == g.q[0] + static_cast<size_t>(i);
  if (consecutive && !any(nonzero)) {
    const Lanes zero = splat(0.0);  // +0, as the scalar stores wrote: one register per layer's worth
    for (size_t l = 0; l < g.L; ++l) __builtin_memcpy(g.d.damage + g.q[0] * g.L + l * kLanes, &zero, sizeof(Lanes));
    return;
  }
  for (int i = 0; i < kLanes; ++i) {
    if (!((g.active >> i) & 1u) || status[i] != kType4Ok) continue;
    for (size_t l = 0; l < g.L; ++l) {
      const size_t ql = g.q[i] * g.L + l;
      const double c = c_new[l][i];
      g.d.damage[ql] = c;
      if (c > g.d.damage_history[ql]) g.d.damage_history[ql] = c;
    }
  }
}

// Forces on the support, -sum_k R_s,k dPsi/d(jet_k), from the layer sums K_alpha = dPsi/dg_alpha and
// C_alpha = xi3 K_alpha through the adjoint of the KL basis (kl_basis_adjoint with K3 = 0).
SF_INLINE void lane_support_forces(const LaneGroup& g, const LaneJet& j, const Lanes3& K1, const Lanes3& K2,
                                   const Lanes3& C1, const Lanes3& C2, shellfrac::shell::Type4BatchResult& out) {
  auto project = [&](const Lanes3& c) { return j.inv_len * (c - dot(j.nrm, c) * j.nrm); };
  const Lanes3 g_dv1 = project(C1), g_dv2 = project(C2);
  const Lanes3 pv1 = project(j.dv1), pv2 = project(j.dv2);
  Lanes3 g_v = zero3();
  g_v = g_v - j.inv_len * (dot(j.nrm, j.dv1) * g_dv1 + dot(C1, j.nrm) * pv1 + dot(C1, j.dn1) * j.nrm);
  g_v = g_v - j.inv_len * (dot(j.nrm, j.dv2) * g_dv2 + dot(C2, j.nrm) * pv2 + dot(C2, j.dn2) * j.nrm);
  Lanes3 ga1 = K1 + cross(j.a2, g_v);
  Lanes3 ga2 = K2 + cross(g_v, j.a1);
  const Lanes3 ga11 = cross(j.a2, g_dv1);
  ga2 = ga2 + cross(g_dv1, j.a11);
  ga1 = ga1 + cross(j.a12, g_dv1);
  Lanes3 ga12 = cross(g_dv1, j.a1);
  ga12 = ga12 + cross(j.a2, g_dv2);
  ga2 = ga2 + cross(g_dv2, j.a12);
  ga1 = ga1 + cross(j.a22, g_dv2);
  const Lanes3 ga22 = cross(g_dv2, j.a1);
  for (int s = 0; s < g.b.n; ++s) {
    const Lanes r1 = g.basis(s, 0), r2 = g.basis(s, 1), r11 = g.basis(s, 2), r12 = g.basis(s, 3), r22 = g.basis(s, 4);
    const Lanes fx = -(r1 * ga1.x + r2 * ga2.x + r11 * ga11.x + r12 * ga12.x + r22 * ga22.x);
    const Lanes fy = -(r1 * ga1.y + r2 * ga2.y + r11 * ga11.y + r12 * ga12.y + r22 * ga22.y);
    const Lanes fz = -(r1 * ga1.z + r2 * ga2.z + r11 * ga11.z + r12 * ga12.z + r22 * ga22.z);
    __builtin_memcpy(out.force[s][0] + g.o, &fx, sizeof(Lanes));
    __builtin_memcpy(out.force[s][1] + g.o, &fy, sizeof(Lanes));
    __builtin_memcpy(out.force[s][2] + g.o, &fz, sizeof(Lanes));
  }
}

// Lanes o .. o + kLanes - 1 of the batch. Fracturing is a template parameter so that the damage law's
// per-point values do not hold registers in the kernel of patches without it.
template <bool Fracturing>
SF_INLINE void lane_group(const shellfrac::shell::Type4Data& d, const shellfrac::shell::Type4Batch& b,
                          shellfrac::shell::Type4BatchResult& out, int o) {
  using namespace shellfrac::shell;
  const LaneGroup g{d, b, o, b.q + o, b.active >> o, static_cast<size_t>(d.layers)};
  const size_t L = g.L;
  const LaneJet j = lane_jet(g);
  LaneMask failed = j.degenerate;
  LaneMask runaway = splat_int(0);
  const Lanes given = gather([&](int i) { return b.r33[o + i]; });
  // Per point material of the damage law (the same for every layer).
  Lanes sigma_f = splat(0.0), H = splat(0.0);
  LaneMask sigma_positive = splat_int(0);  // part of the damage pre-check that no layer changes
  if constexpr (Fracturing) {
    sigma_f = gather([&](int i) { return d.failure_stress[g.q[i]]; });
    H = gather([&](int i) { return d.brittleness[g.q[i]]; });
    sigma_positive = sigma_f > 0.0;
  }
  Lanes3 K1 = zero3(), K2 = zero3(), C1 = zero3(), C2 = zero3();
  Lanes c_new[kType4MaxLayers];  // damage per layer, written back below
  // Every layer's metric first, then their fibre stretches in one Newton loop (independent chains that the
  // core can overlap), then stress, damage and forces layer by layer.
  Lanes ref[kType4MaxLayers][4];
  LaneMetric metric[kType4MaxLayers];
  Lanes lnJ[kType4MaxLayers], ln_l3[kType4MaxLayers], l3_sq[kType4MaxLayers];
  for (size_t l = 0; l < L; ++l) {
    const double xi3 = d.mid_surface ? 0.0 : d.xi3[l];
    lane_reference(g, d.mid_surface ? L / 2 : l, ref[l]);
    metric[l] = lane_metric(j.a1 + xi3 * j.dn1, j.a2 + xi3 * j.dn2, ref[l]);
    lnJ[l] = metric[l].lnJ;
    ln_l3[l] = l3_sq[l] = splat(0.0);
  }
  if (d.model == TransverseModel::Condensed) lane_log_fibre_stretches(lnJ, L, d.mu, d.lambda, ln_l3, l3_sq);
  for (size_t l = 0; l < L; ++l) {
    const double xi3 = d.mid_surface ? 0.0 : d.xi3[l];
    const size_t lref = d.mid_surface ? L / 2 : l;
    Lanes V;
    if (b.volume_lanes)
      __builtin_memcpy(&V, b.volume_lanes + l * kType4Lanes + o, sizeof(Lanes));
    else
      V = gather([&](int i) { return d.volume[g.q[i] * L + l]; });
    // g_1, g_2 again rather than kept per layer since the metric pass: six multiply-adds against registers
    // held across the Newton loop.
    const Lanes3 g1 = j.a1 + xi3 * j.dn1, g2 = j.a2 + xi3 * j.dn2;
    LaneStress st = lane_stress_of(metric[l], ref[l], d.mu, d.lambda, d.model, given, ln_l3[l], l3_sq[l]);
    if (d.plastic) lane_plastic_return(g, l, lref, g1, g2, given, failed, ref[l], st);
    // The first failing layer decides a lane's status, as the scalar loop returns there.
    const LaneMask undecided = ~(failed | runaway);
    failed = failed | (undecided & ~st.ok);
    runaway = runaway | (undecided & st.ok & (st.J > kRunawayAreaRatio));
    Lanes t11 = st.t11, t12 = st.t12, t22 = st.t22;
    if constexpr (Fracturing) {
      // The stored damage matters only to the monotone rule.
      const Lanes c_old = d.monotone ? gather([&](int i) { return d.damage[g.q[i] * L + l]; }) : splat(0.0);
      const Lanes normal = d.plane_strain ? d.lambda * st.lnJ : splat(0.0);
      const LaneMask always = d.monotone ? sigma_positive & (c_old <= 0.0) : sigma_positive;  // c_old = 0 otherwise
      if (all(lane_surely_intact(st, g1, g2, d.plane_strain, normal, sigma_f, always))) {
        c_new[l] = d.monotone ? vmax(splat(0.0), c_old) : splat(0.0);  // lane_damage's c; tau is unchanged
      } else {
        const Lanes lambda3 = d.model == TransverseModel::Given ? given : vexp(st.ln_lambda3);
        lane_damage(t11, t12, t22, g1, g2, st.J * lambda3, normal, sigma_f, H, c_old, d.monotone, d.residual, c_new[l]);
      }
    }
    // dPsi/dg_alpha = V tau^{alpha beta} g_beta
    const Lanes3 k1 = V * (t11 * g1 + t12 * g2);
    const Lanes3 k2 = V * (t12 * g1 + t22 * g2);
    K1 = K1 + k1;
    K2 = K2 + k2;
    C1 = C1 + xi3 * k1;
    C2 = C2 + xi3 * k2;
  }
  // Per lane status; state write-back for the active lanes that did not fail.
  int* status = out.status + o;
  for (int i = 0; i < kLanes; ++i)
    status[i] = failed[i] ? kType4Degenerate : runaway[i] ? kType4Runaway : kType4Ok;
  if constexpr (Fracturing) lane_store_damage(g, c_new, failed, runaway, status);
  lane_support_forces(g, j, K1, K2, C1, C2, out);
}

SF_INLINE void batch_kernel(const shellfrac::shell::Type4Data& d, const shellfrac::shell::Type4Batch& b,
                            shellfrac::shell::Type4BatchResult& out) {
  static_assert(shellfrac::shell::kType4Lanes % kLanes == 0, "a batch is a whole number of lane groups");
  for (int o = 0; o < shellfrac::shell::kType4Lanes; o += kLanes) {
    if (d.fracturing)
      lane_group<true>(d, b, out, o);
    else
      lane_group<false>(d, b, out, o);
  }
}
