// The transfer kernels of SolidGrid (brittle/solid_transfer.hpp), written on four-double vectors of the
// compiler's generic vector extension (GCC and Clang): one AVX register, two SSE2 ones. Included by
// solid_transfer_generic.cpp and solid_transfer_avx2.cpp, each inside an anonymous namespace and compiled
// with its own instruction set, so every function here has internal linkage and is force-inlined (a shared
// inline symbol would let the linker hand AVX2 code to a machine without it). For the same reason the
// kernels touch no Eigen code: the particle arrays are read as plain doubles (a Vector3d is 3 doubles, a
// Matrix3d 9 in column-major order).
//
// A grid node is the four doubles (m, p_x, p_y, p_z) and so one vector; the kernels keep a particle's
// per-node terms in the same layout, lane 0 for the mass.
//
// Differences from the plain formulas are round-off only: products are regrouped (a stencil row's weight
// is applied once per row) and, with FMA, fused.

#define SB_INLINE static inline __attribute__((always_inline))

#if defined(__AVX__)
typedef double V4 __attribute__((vector_size(32)));
SB_INLINE V4 make4(double a, double b, double c, double d) { return V4{a, b, c, d}; }
SB_INLINE double lane(const V4& v, int i) { return v[i]; }
#else
// Without AVX GCC lowers 32-byte generic vectors through the stack; two named 16-byte halves stay in
// SSE2 registers (as in shell/simd_lanes.hpp).
typedef double V2 __attribute__((vector_size(16)));
struct V4 {
  V2 a, b;
};
SB_INLINE V4 make4(double w, double x, double y, double z) { return V4{V2{w, x}, V2{y, z}}; }
SB_INLINE double lane(const V4& v, int i) { return i < 2 ? v.a[i] : v.b[i - 2]; }
SB_INLINE V4 operator+(const V4& u, const V4& v) { return V4{u.a + v.a, u.b + v.b}; }
SB_INLINE V4 operator*(const V4& u, double c) { return V4{u.a * c, u.b * c}; }
SB_INLINE V4 operator*(double c, const V4& u) { return V4{c * u.a, c * u.b}; }
SB_INLINE V4& operator+=(V4& u, const V4& v) {
  u.a += v.a;
  u.b += v.b;
  return u;
}
#endif

SB_INLINE V4 load4(const double* p) {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
SB_INLINE void store4(double* p, const V4& v) { std::memcpy(p, &v, sizeof v); }

// Quadratic B-spline weights of a particle on its 3 x 3 x 3 stencil (thesis Eq. 2.10), the offsets
// x_i - x_p per axis, and the index of the stencil's first node.
struct Stencil {
  long base;
  double w[3][3];
  double d[3][3];
};

template <class Grid>
SB_INLINE void make_stencil(const double* x, const Grid& g, Stencil& st) {
  const long stride[3] = {1, g.stride_y, g.stride_z};
  st.base = 0;
  for (int a = 0; a < 3; ++a) {
    const double q = x[a] * g.inv_dx;
    const int b = static_cast<int>(std::floor(q - 0.5));
    const double f = q - b;  // in [0.5, 1.5)
    st.base += (b - g.lo[a]) * stride[a];
    st.w[a][0] = 0.5 * (1.5 - f) * (1.5 - f);
    st.w[a][1] = 0.75 - (f - 1.0) * (f - 1.0);
    st.w[a][2] = 0.5 * (f - 0.5) * (f - 0.5);
    st.d[a][0] = -f * g.dx;
    st.d[a][1] = (1.0 - f) * g.dx;
    st.d[a][2] = (2.0 - f) * g.dx;
  }
}

// p2g. Node i of the stencil receives w_i (m_p v_p + Q (x_i - x_p)) in its momentum and w_i m_p in its mass,
// with Q = m_p C_p - dt D^-1 V^0 J sigma_p (thesis Eq. 2.23, 2.24; D^-1 = 4 / h^2 for quadratic
// B-splines). Written per stencil row (fixed j, k) as
//   node_i += wx_i (w_yz row) + (wx_i dx_i) (w_yz q_x),  row = (m_p, m_p v_p + Q_{.,1} dy_j + Q_{.,2} dz_k),
// q_x = (0, Q_{.,0}): two multiply-adds per node. Near a crack the field of each node comes from the
// particle's mask and the node's crack normal gains +-w m_p n_p (field 0: +, field 1: -).
void scatter_kernel(const TransferGrid& g, const SolidView& s, double dt, const uint32_t* order, size_t begin, size_t end) {
  const double stress_scale = dt * 4.0 * g.inv_dx * g.inv_dx;  // dt D^-1
  const long sy = g.stride_y, sz = g.stride_z;
  for (size_t e = begin; e < end; ++e) {
    const uint32_t p = order[e];
    Stencil st;
    make_stencil(reinterpret_cast<const double*>(s.x + p), g, st);
    const double mp = s.m[p];
    const double* v = reinterpret_cast<const double*>(s.v + p);
    const double* C = reinterpret_cast<const double*>(s.C + p);
    const double* S = reinterpret_cast<const double*>(s.stress + p);
    double Q[9];
    for (int c = 0; c < 9; ++c) Q[c] = mp * C[c] - stress_scale * S[c];
    const V4 qx = make4(0.0, Q[0], Q[1], Q[2]), qy = make4(0.0, Q[3], Q[4], Q[5]), qz = make4(0.0, Q[6], Q[7], Q[8]);
    const V4 m4 = make4(mp, mp * v[0], mp * v[1], mp * v[2]);
    const double wx[3] = {st.w[0][0], st.w[0][1], st.w[0][2]};
    const double wxd[3] = {st.w[0][0] * st.d[0][0], st.w[0][1] * st.d[0][1], st.w[0][2] * st.d[0][2]};
    const FieldMask mask = s.mask ? s.mask[p] : 0;
    const int32_t slot = g.normal && s.near_slot ? s.near_slot[p] : -1;
    if (mask == 0 && slot < 0) {  // most particles: one field, no crack normal
      GridNode* const f0 = g.field[0] + st.base;
      for (int k = 0; k < 3; ++k) {
        const V4 rowz = m4 + qz * st.d[2][k];
        for (int j = 0; j < 3; ++j) {
          const double wyz = st.w[1][j] * st.w[2][k];
          const V4 a = wyz * (rowz + qy * st.d[1][j]), b = wyz * qx;
          double* nd = &f0[j * sy + k * sz].m;
          for (int i = 0; i < 3; ++i) store4(nd + 4 * i, load4(nd + 4 * i) + a * wx[i] + b * wxd[i]);
        }
      }
      continue;
    }
    V4 n4 = make4(0, 0, 0, 0);
    if (slot >= 0) {
      const double* n = reinterpret_cast<const double*>(s.near_normal + slot);
      n4 = make4(n[0], n[1], n[2], 0.0) * mp;
    }
    for (int k = 0; k < 3; ++k) {
      const V4 rowz = m4 + qz * st.d[2][k];
      for (int j = 0; j < 3; ++j) {
        const double wyz = st.w[1][j] * st.w[2][k];
        const V4 a = wyz * (rowz + qy * st.d[1][j]), b = wyz * qx;
        const long row = st.base + j * sy + k * sz;
        for (int i = 0; i < 3; ++i) {
          const unsigned field = (mask >> (i + 3 * j + 9 * k)) & 1u;
          double* nd = &g.field[field][row + i].m;
          store4(nd, load4(nd) + a * wx[i] + b * wxd[i]);
          if (slot >= 0) {
            const double w = wx[i] * wyz;
            double* nn = g.normal + 4 * (row + i);
            store4(nn, load4(nn) + (field ? -w : w) * n4);
          }
        }
      }
    }
  }
}

// g2p. v_p = sum w v_i, B = sum w v_i (x_i - x_p)^T, C_p = D^-1 B (Eq. 2.20, 2.25), F <- (I + dt C) F
// (Eq. 2.26), x <- x + dt v (Eq. 2.21). Per stencil row (fixed j, k) the row sums s = sum_i wx_i n_i and
// t = sum_i wx_i dx_i n_i are formed first; then v += w_yz s, B_{.,0} += w_yz t, B_{.,1} += w_yz dy_j s,
// B_{.,2} += w_yz dz_k s. (The nodes' lane 0 holds the mass and is carried along unused.)
void gather_kernel(const ConstTransferGrid& g, const SolidView& s, double dt, size_t begin, size_t end) {
  const double inv_d = 4.0 * g.inv_dx * g.inv_dx;
  const long sy = g.stride_y, sz = g.stride_z;
  for (size_t p = begin; p < end; ++p) {
    double* x = reinterpret_cast<double*>(s.x + p);
    Stencil st;
    make_stencil(x, g, st);
    const FieldMask mask = s.mask ? s.mask[p] : 0;
    const double wx[3] = {st.w[0][0], st.w[0][1], st.w[0][2]};
    const double wxd[3] = {st.w[0][0] * st.d[0][0], st.w[0][1] * st.d[0][1], st.w[0][2] * st.d[0][2]};
    V4 sv = make4(0, 0, 0, 0), bx = sv, by = sv, bz = sv;
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) {
        const long row = st.base + j * sy + k * sz;
        const double *n0, *n1, *n2;
        if (mask == 0) {
          n0 = &g.field[0][row].m;
          n1 = n0 + 4;
          n2 = n0 + 8;
        } else {
          const unsigned bit = 3 * j + 9 * k;
          n0 = &g.field[(mask >> bit) & 1u][row].m;
          n1 = &g.field[(mask >> (bit + 1)) & 1u][row + 1].m;
          n2 = &g.field[(mask >> (bit + 2)) & 1u][row + 2].m;
        }
        const V4 a0 = load4(n0), a1 = load4(n1), a2 = load4(n2);
        const V4 rs = a0 * wx[0] + a1 * wx[1] + a2 * wx[2];
        const V4 rt = a0 * wxd[0] + a1 * wxd[1] + a2 * wxd[2];
        const double wyz = st.w[1][j] * st.w[2][k];
        sv += wyz * rs;
        bx += wyz * rt;
        by += (wyz * st.d[1][j]) * rs;
        bz += (wyz * st.d[2][k]) * rs;
      }
    }
    // M = I + dt C as three column vectors in lanes 1..3 (lane 0 unused); F's columns likewise.
    const double h = dt * inv_d;
    const V4 m0 = make4(0, 1, 0, 0) + h * bx, m1 = make4(0, 0, 1, 0) + h * by, m2 = make4(0, 0, 0, 1) + h * bz;
    double* F = reinterpret_cast<double*>(s.F + p);
    // Column c of the product goes to Fn[3 c + 1 .. 3 c + 3] (lanes 1..3 of a store at Fn + 3 c); stored
    // last column first, so that each store's unused lane 0 lands on the previous column's slot before that
    // column is written.
    double Fn[12];
    for (int c = 2; c >= 0; --c) store4(Fn + 3 * c, m0 * F[3 * c] + m1 * F[3 * c + 1] + m2 * F[3 * c + 2]);
    for (int c = 0; c < 9; ++c) F[c] = Fn[1 + c];
    double* v = reinterpret_cast<double*>(s.v + p);
    double* C = reinterpret_cast<double*>(s.C + p);
    for (int a = 0; a < 3; ++a) {
      v[a] = lane(sv, a + 1);
      C[a] = inv_d * lane(bx, a + 1);
      C[3 + a] = inv_d * lane(by, a + 1);
      C[6 + a] = inv_d * lane(bz, a + 1);
      x[a] += dt * lane(sv, a + 1);
    }
  }
}
