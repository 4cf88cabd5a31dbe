// The particle passes of the phase field (brittle/phase_field.hpp; CD-MPM Eq. 6-7): the Laplacian part
// of the operator, y += H x, the assembly of the lumped terms and the update of the particles' c, as
// per-particle kernels beside SolidGrid's transfers. Included after solid_transfer_impl.hpp by
// solid_transfer_generic.cpp and solid_transfer_avx2.cpp, inside their anonymous namespaces, so it is
// compiled once per instruction set and picked with them at run time.
//
// A stencil row (fixed j, k: three nodes along x) is one four-double vector with a zero fourth lane, so
// the sums over i are vector multiply-adds and only the three final dot products are horizontal. Rows
// are read and written three doubles at a time: the fourth node may belong to a slab another thread
// writes, or lie past the end of the grid.

#if !defined(__AVX__)
SB_INLINE V4 operator*(const V4& u, const V4& v) { return V4{u.a * v.a, u.b * v.b}; }
#endif

// Three doubles to and from a vector's lanes 0-2 (lane 3 zero), as a 16- and an 8-byte access: a
// 24-byte memcpy into a vector goes through the stack and stalls store forwarding. (The AVX2 file
// includes immintrin.h.)
#if defined(__AVX__)
SB_INLINE V4 load3(const double* p) {
  return (V4)_mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}
SB_INLINE void store3(double* p, const V4& v) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128((__m256d)v));
  _mm_store_sd(p + 2, _mm256_extractf128_pd((__m256d)v, 1));
}
#else
SB_INLINE V4 load3(const double* p) {
  V2 lo, hi = V2{p[2], 0.0};
  std::memcpy(&lo, p, sizeof lo);
  return V4{lo, hi};
}
SB_INLINE void store3(double* p, const V4& v) {
  std::memcpy(p, &v.a, sizeof v.a);
  p[2] = v.b[0];
}
#endif
SB_INLINE double dot3(const V4& u, const V4& v) {
  const V4 m = u * v;
  return lane(m, 0) + lane(m, 1) + lane(m, 2);
}

// The gradient factors d[axis][i] of a particle's stencil (make_stencil): the derivative of the quadratic
// B-spline (Eq. 2.10), or CD-MPM's MLS factor 4/dx^2 w (x_i - x_p) of sec. 4.2.2. grad Theta_ijk is then
// (d_i w_j w_k, w_i d_j w_k, w_i w_j d_k).
SB_INLINE void gradient_factors(const Stencil& st, const ConstTransferGrid& g, bool mls_gradient, double d[3][3]) {
  const double mls = 4.0 * g.inv_dx * g.inv_dx;
  for (int ax = 0; ax < 3; ++ax) {
    if (mls_gradient) {
      for (int i = 0; i < 3; ++i) d[ax][i] = mls * st.w[ax][i] * st.d[ax][i];
    } else {
      const double f = -st.d[ax][0] * g.inv_dx;  // q - base in [0.5, 1.5)
      d[ax][0] = -(1.5 - f) * g.inv_dx;
      d[ax][1] = -2.0 * (f - 1.0) * g.inv_dx;
      d[ax][2] = (f - 0.5) * g.inv_dx;
    }
  }
}

// A particle's stencil with its gradient factors: what the operator and the assembly read.
struct GradientStencil {
  Stencil st;
  double d[3][3];
};

SB_INLINE void make_gradient_stencil(const double* x, const ConstTransferGrid& g, bool mls_gradient, GradientStencil& s) {
  make_stencil(x, g, s.st);
  gradient_factors(s.st, g, mls_gradient, s.d);
}

// The node offset of stencil row (j, k).
SB_INLINE long row_offset(const ConstTransferGrid& g, int j, int k) { return j * g.stride_y + k * g.stride_z; }

// For the particles order[begin..end): grad c_h(x_p) = sum_ijk grad Theta_ijk(x_p) x_ijk, then
// y_ijk += grad Theta_ijk(x_p) . grad c_h V_p scale, with grad Theta_ijk = (g_i w_j w_k, w_i g_j w_k,
// w_i w_j g_k) and g the spline derivative or CD-MPM's MLS factor 4/dx^2 w (x_i - x_p) (sec. 4.2.2).
void phase_field_operator_kernel(const ConstTransferGrid& g, const PhaseFieldOperatorArgs& a, const uint32_t* order,
                                 size_t begin, size_t end) {
  const V4 zero = make4(0.0, 0.0, 0.0, 0.0);
  for (size_t e = begin; e < end; ++e) {
    const size_t q = order[e];
    GradientStencil s;
    make_gradient_stencil(a.position + 3 * q, g, a.mls_gradient, s);
    const long base = s.st.base;
    const double(&w)[3][3] = s.st.w;
    const double(&d)[3][3] = s.d;
    const V4 wx = make4(w[0][0], w[0][1], w[0][2], 0.0), dx = make4(d[0][0], d[0][1], d[0][2], 0.0);
    // Sum over j per k (P with w_j, Q with g_j), then over k.
    V4 wp = zero, dp = zero, wq = zero;
    for (int k = 0; k < 3; ++k) {
      V4 P = zero, Q = zero;
      for (int j = 0; j < 3; ++j) {
        const V4 row = load3(a.x + base + row_offset(g, j, k));
        P += w[1][j] * row;
        Q += d[1][j] * row;
      }
      wp += w[2][k] * P;
      dp += d[2][k] * P;
      wq += w[2][k] * Q;
    }
    const double scale = a.volume[q] * a.scale;
    const double gx = dot3(dx, wp) * scale, gy = dot3(wx, wq) * scale, gz = dot3(wx, dp) * scale;
    for (int k = 0; k < 3; ++k) {
      const double vx = gx * w[2][k], vy = gy * w[2][k], vz = gz * d[2][k];
      for (int j = 0; j < 3; ++j) {
        double* row = a.y + base + row_offset(g, j, k);
        store3(row, load3(row) + (vx * w[1][j]) * dx + (vy * d[1][j] + vz * w[1][j]) * wx);
      }
    }
  }
}

// The assembly of the system for the particles order[begin..end) (brittle/phase_field.hpp): per node the
// kernel weight sum, sum w c_p, the lumped M_ii, r_i and H_ii.
void phase_field_assembly_kernel(const ConstTransferGrid& g, const PhaseFieldAssemblyArgs& a, const uint32_t* order,
                                 size_t begin, size_t end) {
  for (size_t e = begin; e < end; ++e) {
    const size_t q = order[e];
    GradientStencil s;
    make_gradient_stencil(a.position + 3 * q, g, a.mls_gradient, s);
    const long base = s.st.base;
    const double(&w)[3][3] = s.st.w;
    const double(&d)[3][3] = s.d;
    const double V = a.volume[q], cq = a.c[q];
    const double mass = V * (a.history_factor * a.history[q] + a.mass_constant);  // M_ii integrand
    const double source = V * (a.source_constant + cq * a.inv_dt);                // r_i integrand
    const double stiffness = V * a.stiffness;                                      // H_ii integrand
    const V4 share = make4(1.0, cq, mass, source);
    const V4 wx = make4(w[0][0], w[0][1], w[0][2], 0.0), dx = make4(d[0][0], d[0][1], d[0][2], 0.0);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) {
        const long at = base + row_offset(g, j, k);
        const double wjk = w[1][j] * w[2][k];
        for (int i = 0; i < 3; ++i) {
          double* node = a.lumped + 4 * (at + i);
          store4(node, load4(node) + (wjk * w[0][i]) * share);
        }
        // |grad Theta|^2 per node: (g_i w_j w_k)^2 + (w_i g_j w_k)^2 + (w_i w_j g_k)^2.
        const V4 gx = wjk * dx, gy = (d[1][j] * w[2][k]) * wx, gz = (w[1][j] * d[2][k]) * wx;
        store3(a.precond + at, load3(a.precond + at) + stiffness * (gx * gx + gy * gy + gz * gz));
      }
  }
}

// Back to the particles begin..end without healing (sec. 4.2.1): c_p = max(0, min(c_p, c_p + sum_i w_ip
// (c_i^{n+1} - c_i^n))).
void phase_field_gather_kernel(const ConstTransferGrid& g, const PhaseFieldGatherArgs& a, size_t begin, size_t end) {
  for (size_t q = begin; q < end; ++q) {
    Stencil st;
    make_stencil(a.position + 3 * q, g, st);
    const long base = st.base;
    const double(&w)[3][3] = st.w;
    const V4 wx = make4(w[0][0], w[0][1], w[0][2], 0.0);
    V4 sum = make4(0.0, 0.0, 0.0, 0.0);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) {
        const long at = base + row_offset(g, j, k);
        sum += (w[1][j] * w[2][k]) * (load3(a.c_new + at) + (-1.0) * load3(a.c_old + at));
      }
    const double cq = a.c[q], change = dot3(wx, sum);
    a.c[q] = std::max(0.0, std::min(cq, cq + change));
  }
}
