#include "shell/mls_basis.hpp"

#include <Eigen/Cholesky>
#include <cstdio>
#include <limits>

#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::shell {

namespace {

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

void clear_result(MlsBasis& out) {
  out.index.clear();
  out.R.clear();
  out.R1.clear();
  out.R2.clear();
  out.R11.clear();
  out.R12.clear();
  out.R22.clear();
}

void fail(MlsBasis& out, MlsStatus status, std::string reason) {
  clear_result(out);
  out.ok = false;
  out.status = status;
  out.reason = std::move(reason);
}

}  // namespace

// thesis Eq. 4.18 with the second branch corrected to the C^2 cubic spline (DESIGN.md, known misprints).
CubicWeight cubic_weight(double r) {
  if (r <= 0.5) return {2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r, -8.0 * r + 12.0 * r * r, -8.0 + 24.0 * r};
  if (r < 1.0) {
    const double s = 1.0 - r;  // 4/3 - 4r + 4r^2 - 4/3 r^3 == (4/3)(1 - r)^3
    return {4.0 / 3.0 * s * s * s, -4.0 * s * s, 8.0 * s};
  }
  return {0.0, 0.0, 0.0};
}

// Diffraction weight (Organ, Fleming, Terry, Belytschko 1996, Eq. for d_hat): with s0 = |e| (straight
// distance), s2 = |r| (point to tip) and s1 (tip to control point), the ratio g = (s1 + s2) / s0 >= 1 says
// how much longer the way around the tip is; d_hat = g^lambda s0. Here the scaled offset e is stretched by
//   f = 1 + (g^lambda - 1) chi,   chi = s2^2 / (s2^2 + eps^2),
// so both tensor-product factors see |f e_i| (d_hat / d = f when eps = 0). On the line through the control
// point and the tip g = 1 and f = 1: the weight equals the weight it has from the visible side (continuity
// across the crack's extension). chi fades the stretch out within ~eps of the tip: g - 1 grows like s2 there
// and its second derivatives like 1 / s2; times chi ~ s2^2 / eps^2 the product is C^2 with bounded second
// derivatives (f = 1 exactly at the tip). Derivatives with respect to y (the evaluation point), de/dy = -I:
//   s0_a = -e_a / s0, s0_ab = (delta_ab - e_a e_b / s0^2) / s0,
//   s2_a = r_a / s2,  s2_ab = (delta_ab - r_a r_b / s2^2) / s2,
//   g_a = (s2_a - g s0_a) / s0,  g_ab = (s2_ab - g_a s0_b - g_b s0_a - g s0_ab) / s0   (from g s0 = s1 + s2),
//   G = g^lambda - 1, G_a = lambda g^(lambda-1) g_a, G_ab = lambda (lambda-1) g^(lambda-2) g_a g_b + lambda g^(lambda-1) g_ab,
//   chi_a = 2 eps^2 r_a / (q + eps^2)^2, chi_ab = 2 eps^2 delta_ab / (q + eps^2)^2 - 8 eps^2 r_a r_b / (q + eps^2)^3 (q = s2^2),
//   f_a = G_a chi + G chi_a, f_ab = G_ab chi + G_a chi_b + G_b chi_a + G chi_ab,
//   u_i = f e_i: u_i,a = f_a e_i - f delta_ia, u_i,ab = f_ab e_i - f_a delta_ib - f_b delta_ia,
//   W = A(u_1) B(u_2) with A(u) = w(|u|) (Eq. 4.18): A' = w'(|u|) sign(u), A'' = w''(|u|).
WeightDerivatives diffracted_weight(const Eigen::Vector2d& e, const Eigen::Vector2d& r, double s1, double lambda,
                                    double eps) {
  const double s0 = e.norm();
  const double s2 = r.norm();
  double f = 1.0;
  Eigen::Vector2d fa = Eigen::Vector2d::Zero();
  Eigen::Matrix2d fab = Eigen::Matrix2d::Zero();
  if (s2 > 0.0 && s0 > 0.0) {  // at the tip itself f = 1 with zero derivatives (f - 1 = O(s2^3))
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    const Eigen::Vector2d s0a = -e / s0;
    const Eigen::Matrix2d s0ab = (I - e * e.transpose() / (s0 * s0)) / s0;
    const Eigen::Vector2d s2a = r / s2;
    const Eigen::Matrix2d s2ab = (I - r * r.transpose() / (s2 * s2)) / s2;
    const double g = std::max(1.0, (s1 + s2) / s0);  // >= 1 by the triangle inequality; round-off only
    const Eigen::Vector2d ga = (s2a - g * s0a) / s0;
    const Eigen::Matrix2d gab = (s2ab - ga * s0a.transpose() - s0a * ga.transpose() - g * s0ab) / s0;
    const double gl = std::pow(g, lambda);
    const double G = gl - 1.0;
    const Eigen::Vector2d Ga = lambda * (gl / g) * ga;
    const Eigen::Matrix2d Gab = lambda * (lambda - 1.0) * (gl / (g * g)) * ga * ga.transpose() + lambda * (gl / g) * gab;
    double chi = 1.0;
    Eigen::Vector2d chia = Eigen::Vector2d::Zero();
    Eigen::Matrix2d chiab = Eigen::Matrix2d::Zero();
    if (eps > 0.0) {
      const double q = s2 * s2, e2 = eps * eps, den = q + e2;
      chi = q / den;
      chia = (2.0 * e2 / (den * den)) * r;
      chiab = (2.0 * e2 / (den * den)) * I - (8.0 * e2 / (den * den * den)) * r * r.transpose();
    }
    f = 1.0 + G * chi;
    fa = Ga * chi + G * chia;
    fab = Gab * chi + Ga * chia.transpose() + chia * Ga.transpose() + G * chiab;
  }
  const Eigen::Vector2d u = f * e;
  // du_i / dy_a and d2u_i / dy_a dy_b
  Eigen::Matrix2d ua;  // ua(i, a)
  for (int i = 0; i < 2; ++i)
    for (int a = 0; a < 2; ++a) ua(i, a) = fa(a) * e(i) - (i == a ? f : 0.0);
  Eigen::Matrix2d uab[2];
  for (int i = 0; i < 2; ++i)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        uab[i](a, b) = fab(a, b) * e(i) - (i == b ? fa(a) : 0.0) - (i == a ? fa(b) : 0.0);
  const CubicWeight A = cubic_weight(std::abs(u(0)));
  const CubicWeight B = cubic_weight(std::abs(u(1)));
  const double A1 = u(0) > 0.0 ? A.dw : -A.dw, B1 = u(1) > 0.0 ? B.dw : -B.dw;
  WeightDerivatives D{};
  D.stretch = f;
  D.W = A.w * B.w;
  if (!(D.W > 0.0)) return D;
  double W1[2], W2[2][2];
  for (int a = 0; a < 2; ++a) W1[a] = A1 * ua(0, a) * B.w + A.w * B1 * ua(1, a);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      W2[a][b] = A.ddw * ua(0, a) * ua(0, b) * B.w + A1 * uab[0](a, b) * B.w + A1 * ua(0, a) * B1 * ua(1, b) +
                 A1 * ua(0, b) * B1 * ua(1, a) + A.w * B.ddw * ua(1, a) * ua(1, b) + A.w * B1 * uab[1](a, b);
  D.W1 = W1[0];
  D.W2 = W1[1];
  D.W11 = W2[0][0];
  D.W12 = W2[0][1];
  D.W22 = W2[1][1];
  return D;
}

namespace detail {

double weight_reach(const Eigen::Vector2d& xi, double pu, double pv, double tu, double tv, double cell_u,
                    double cell_v, const TipWeights& tip) {
  const Eigen::Vector2d e((pu - xi.x()) / cell_u, (pv - xi.y()) / cell_v);
  const double plain = e.cwiseAbs().maxCoeff();
  if (std::isnan(tu)) return plain;
  // diffracted_weight's stretch f is the same at every support size, so it is taken in cell units (where
  // the fade radius is tip.radius itself); only its value is used here.
  const Eigen::Vector2d r((xi.x() - tu) / cell_u, (xi.y() - tv) / cell_v);
  const double s1 = Eigen::Vector2d((pu - tu) / cell_u, (pv - tv) / cell_v).norm();
  return diffracted_weight(e, r, s1, tip.lambda, tip.radius).stretch * plain;
}

}  // namespace detail

ControlGrid ControlGrid::from_surface(const nurbs::NurbsSurface& surface) {
  ControlGrid grid;
  const nurbs::KnotVector& ku = surface.knots_u();
  const nurbs::KnotVector& kv = surface.knots_v();
  grid.u.resize(static_cast<std::size_t>(ku.num_basis()));
  grid.v.resize(static_cast<std::size_t>(kv.num_basis()));
  for (int i = 0; i < ku.num_basis(); ++i) grid.u[static_cast<std::size_t>(i)] = ku.greville(i);
  for (int j = 0; j < kv.num_basis(); ++j) grid.v[static_cast<std::size_t>(j)] = kv.greville(j);
  // Mean cell size: exact for the uniform knot vectors of the built-in patches.
  grid.cell_u = (ku.domain_end() - ku.domain_begin()) / ku.num_spans();
  grid.cell_v = (kv.domain_end() - kv.domain_begin()) / kv.num_spans();
  return grid;
}

namespace detail {

bool check_mls_inputs(const Eigen::Vector2d& xi, double cell_u, double cell_v, const MlsSettings& s,
                      MlsBasis& out) {
  out.factor = 0.0;
  out.rcond = 0.0;
  std::string why;
  if (!xi.allFinite()) {
    why = "evaluation point (" + fmt(xi.x()) + ", " + fmt(xi.y()) + ") is not finite";
  } else if (!(std::isfinite(cell_u) && cell_u > 0.0 && std::isfinite(cell_v) && cell_v > 0.0)) {
    why = "cell sizes (" + fmt(cell_u) + ", " + fmt(cell_v) + ") must be finite and > 0";
  } else if (!(std::isfinite(s.initial_factor) && s.initial_factor > 0.0 && std::isfinite(s.max_factor) &&
               s.max_factor >= s.initial_factor)) {
    why = "support factors must satisfy 0 < initial_factor (" + fmt(s.initial_factor) + ") <= max_factor (" +
          fmt(s.max_factor) + ")";
  } else if (!(s.support_margin > 1.0 && std::isfinite(s.support_margin))) {
    why = "support_margin = " + fmt(s.support_margin) + " must be finite and > 1";
  } else if (!(s.growth > 1.0 && std::isfinite(s.growth))) {
    why = "growth = " + fmt(s.growth) + " must be finite and > 1";
  } else if (s.min_neighbours < 1) {
    why = "min_neighbours = " + std::to_string(s.min_neighbours) + " must be >= 1";
  } else if (!(s.min_rcond >= 0.0)) {
    why = "min_rcond = " + fmt(s.min_rcond) + " must be >= 0";
  }
  if (why.empty()) return true;
  fail(out, MlsStatus::invalid_input, "MLS basis: " + why);
  return false;
}

// Evaluation in local coordinates: eta = ((xi_k - xi) / d) componentwise, i.e. shifted to the evaluation
// point and scaled by the support size. The MLS approximant is unchanged by an invertible affine change of a
// complete polynomial basis, so R_k and its derivatives are the same as with p(xi) of thesis Eq. 4.16, while
// the moment matrix entries stay O(1) even for cells 0.01 wide (p(xi) itself would give entries spanning
// 1 .. 1e-8 and a useless condition number). The centre is held fixed while differentiating.
MlsAttempt mls_evaluate(const Eigen::Vector2d& xi, double d_u, double d_v, const MlsSettings& settings,
                        MlsBasis& out) {
  MlsBasis::Workspace& w = out.work;
  const std::size_t n = w.index.size();
  for (auto* a : {&w.W, &w.W1, &w.W2, &w.W11, &w.W12, &w.W22, &w.e1, &w.e2}) a->resize(n);
  w.support.resize(n);
  // Weights (Eq. 4.18 in tensor-product form) and their derivatives in scaled coordinates y = xi / d;
  // candidates with W = 0 are dropped, so the arrays are compacted to the m support points. The candidate
  // list itself (index, pu, pv) is kept: a larger support adds to it.
  std::size_t m = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const double e1 = (w.pu[c] - xi.x()) / d_u;  // local coordinate of the control point
    const double e2 = (w.pv[c] - xi.y()) / d_v;
    if (c < w.tu.size() && !std::isnan(w.tu[c])) {  // seen around a crack tip (docs/mls.md, "Tip weights")
      const Eigen::Vector2d e(e1, e2);
      const Eigen::Vector2d r((xi.x() - w.tu[c]) / d_u, (xi.y() - w.tv[c]) / d_v);  // y - y_c
      const double s1 = Eigen::Vector2d((w.pu[c] - w.tu[c]) / d_u, (w.pv[c] - w.tv[c]) / d_v).norm();
      // The fade radius is given in cells; y = xi / d with d = factor * cell (out.factor is set by the caller).
      const double eps = out.factor > 0.0 ? settings.tip.radius / out.factor : settings.tip.radius;
      const WeightDerivatives D = diffracted_weight(e, r, s1, settings.tip.lambda, eps);
      if (!(D.W > 0.0)) continue;
      w.W[m] = D.W;
      w.W1[m] = D.W1;
      w.W2[m] = D.W2;
      w.W11[m] = D.W11;
      w.W12[m] = D.W12;
      w.W22[m] = D.W22;
      w.e1[m] = e1;
      w.e2[m] = e2;
      w.support[m] = w.index[c];
      ++m;
      continue;
    }
    const CubicWeight a = cubic_weight(std::abs(e1));
    const CubicWeight b = cubic_weight(std::abs(e2));
    const double W = a.w * b.w;
    if (!(W > 0.0)) continue;
    // r = |y - y_k| = |e|, dr/dy = -sign(e); dr/dy is squared away in the second derivative.
    const double s1 = e1 > 0.0 ? -1.0 : 1.0;
    const double s2 = e2 > 0.0 ? -1.0 : 1.0;
    w.W[m] = W;
    w.W1[m] = a.dw * s1 * b.w;
    w.W2[m] = a.w * b.dw * s2;
    w.W11[m] = a.ddw * b.w;
    w.W12[m] = a.dw * s1 * b.dw * s2;
    w.W22[m] = a.w * b.ddw;
    w.e1[m] = e1;
    w.e2[m] = e2;
    w.support[m] = w.index[c];
    ++m;
  }
  return mls_solve(m, d_u, d_v, settings, out);
}

namespace {

// With A = sum_k W_k q_k q_k^T (Eq. 4.17, q_k = p(eta_k)) and gamma = A^-1 p(eta) (A is symmetric),
// R_k = W_k q_k . gamma is Eq. 4.16. Differentiating A gamma = p gives
//   A gamma_a  = p_a  - A_a gamma,
//   A gamma_ab = p_ab - A_a gamma_b - A_b gamma_a - A_ab gamma,
// which is Eq. 4.20/4.21 with the A^-1 derivatives expanded, but needs only three NxN solves per derivative
// order with one Cholesky factor of A, and never forms A_a or A_ab (A_a gamma = sum_k W_k,a (q_k . gamma) q_k).
// N = 6: the quadratic basis of Eq. 4.16; N = 3: the linear basis (p_ab = 0).
// The moment matrix A = sum_k W_k q_k q_k^T (thesis Eq. 4.17), with q_k = p(eta_k) (the Eq. 4.16 basis
// in local coordinates) written to w.q.
template <int N>
Eigen::Matrix<double, N, N> moment_matrix(std::size_t m, MlsBasis::Workspace& w) {
  using VecN = Eigen::Matrix<double, N, 1>;
  using MatN = Eigen::Matrix<double, N, N>;
  w.q.resize(static_cast<std::size_t>(N) * m);
  MatN A = MatN::Zero();
  for (std::size_t k = 0; k < m; ++k) {
    Eigen::Map<VecN> q(&w.q[N * k]);
    const double e1 = w.e1[k], e2 = w.e2[k];
    if constexpr (N == 6) {
      q << 1.0, e1, e2, e1 * e1, e1 * e2, e2 * e2;
    } else {
      q << 1.0, e1, e2;
    }
    A.noalias() += w.W[k] * q * q.transpose();
  }
  return A;
}

// gamma = A^-1 p at the evaluation point (eta = 0) and its first and second derivatives, each one solve
// with the factor of A (see above).
template <int N>
struct Gammas {
  using VecN = Eigen::Matrix<double, N, 1>;
  VecN g, g1, g2, g11, g12, g22;
};

template <int N>
Gammas<N> solve_gammas(const Eigen::LLT<Eigen::Matrix<double, N, N>>& A_llt, std::size_t m, const MlsBasis::Workspace& w) {
  using VecN = Eigen::Matrix<double, N, 1>;
  const auto solve = [&](const VecN& b) -> VecN { return A_llt.solve(b); };
  Gammas<N> G;
  G.g = solve(VecN::Unit(0));
  VecN rhs1 = VecN::Unit(1), rhs2 = VecN::Unit(2);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Map<const VecN> q(&w.q[N * k]);
    const double t = q.dot(G.g);
    rhs1.noalias() -= (w.W1[k] * t) * q;
    rhs2.noalias() -= (w.W2[k] * t) * q;
  }
  G.g1 = solve(rhs1);
  G.g2 = solve(rhs2);

  VecN rhs11 = VecN::Zero(), rhs12 = VecN::Zero(), rhs22 = VecN::Zero();
  if constexpr (N == 6) {
    rhs11(3) = 2.0;
    rhs12(4) = 1.0;
    rhs22(5) = 2.0;
  }
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Map<const VecN> q(&w.q[N * k]);
    const double t = q.dot(G.g), t1 = q.dot(G.g1), t2 = q.dot(G.g2);
    rhs11.noalias() -= (2.0 * w.W1[k] * t1 + w.W11[k] * t) * q;
    rhs12.noalias() -= (w.W1[k] * t2 + w.W2[k] * t1 + w.W12[k] * t) * q;
    rhs22.noalias() -= (2.0 * w.W2[k] * t2 + w.W22[k] * t) * q;
  }
  G.g11 = solve(rhs11);
  G.g12 = solve(rhs12);
  G.g22 = solve(rhs22);
  return G;
}

// R_k = W_k q_k . gamma and its derivatives, with the chain rule back to parameter coordinates
// (d/dxi_a = (1/d_a) d/dy_a). False if any value is not finite.
template <int N>
bool write_basis(const Gammas<N>& G, std::size_t m, double d_u, double d_v, MlsBasis& out) {
  using VecN = Eigen::Matrix<double, N, 1>;
  const MlsBasis::Workspace& w = out.work;
  for (auto* a : {&out.R, &out.R1, &out.R2, &out.R11, &out.R12, &out.R22}) a->resize(m);
  const double iu = 1.0 / d_u, iv = 1.0 / d_v;
  double check = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Map<const VecN> q(&w.q[N * k]);
    const double t = q.dot(G.g), t1 = q.dot(G.g1), t2 = q.dot(G.g2);
    const double W = w.W[k], W1 = w.W1[k], W2 = w.W2[k];
    out.R[k] = W * t;                                                               // thesis Eq. 4.16
    out.R1[k] = (W1 * t + W * t1) * iu;                                             // thesis Eq. 4.20
    out.R2[k] = (W2 * t + W * t2) * iv;
    out.R11[k] = (w.W11[k] * t + 2.0 * W1 * t1 + W * q.dot(G.g11)) * iu * iu;  // thesis Eq. 4.21
    out.R12[k] = (w.W12[k] * t + W1 * t2 + W2 * t1 + W * q.dot(G.g12)) * iu * iv;
    out.R22[k] = (w.W22[k] * t + 2.0 * W2 * t2 + W * q.dot(G.g22)) * iv * iv;
    check += out.R[k] + out.R1[k] + out.R2[k] + out.R11[k] + out.R12[k] + out.R22[k];
  }
  return std::isfinite(check);
}

// With A = sum_k W_k q_k q_k^T (Eq. 4.17, q_k = p(eta_k)) and gamma = A^-1 p(eta) (A is symmetric),
// R_k = W_k q_k . gamma is Eq. 4.16. Differentiating A gamma = p gives
//   A gamma_a  = p_a  - A_a gamma,
//   A gamma_ab = p_ab - A_a gamma_b - A_b gamma_a - A_ab gamma,
// which is Eq. 4.20/4.21 with the A^-1 derivatives expanded, but needs only three NxN solves per derivative
// order with one Cholesky factor of A, and never forms A_a or A_ab (A_a gamma = sum_k W_k,a (q_k . gamma) q_k).
// N = 6: the quadratic basis of Eq. 4.16; N = 3: the linear basis (p_ab = 0).
template <int N>
MlsAttempt solve_order(std::size_t m, double d_u, double d_v, const MlsSettings& settings, MlsBasis& out) {
  using VecN = Eigen::Matrix<double, N, 1>;
  using MatN = Eigen::Matrix<double, N, N>;
  out.index.assign(out.work.support.begin(), out.work.support.begin() + static_cast<std::ptrdiff_t>(m));
  const MatN A = moment_matrix<N>(m, out.work);

  MlsAttempt attempt;
  attempt.neighbours = static_cast<int>(m);
  if (attempt.neighbours < settings.min_neighbours || m < static_cast<std::size_t>(N)) {
    attempt.status = MlsStatus::too_few_neighbours;
    out.index.clear();
    return attempt;
  }
  // Conditioning is judged on the Jacobi-equilibrated matrix D^-1/2 A D^-1/2: the quadratic moments are
  // naturally ~50x smaller than the zeroth one, which says nothing about the geometry of the support.
  const VecN diag_scale = A.diagonal().cwiseMax(std::numeric_limits<double>::min()).cwiseSqrt().cwiseInverse();
  const MatN A_eq = diag_scale.asDiagonal() * A * diag_scale.asDiagonal();
  const Eigen::LLT<MatN> llt_eq(A_eq);
  attempt.rcond = llt_eq.info() == Eigen::Success ? llt_eq.rcond() : 0.0;
  out.rcond = attempt.rcond;
  if (!(attempt.rcond >= settings.min_rcond) || !(attempt.rcond > 0.0)) {
    attempt.status = MlsStatus::ill_conditioned;
    out.index.clear();
    return attempt;
  }
  // Solve with A itself: its Cholesky residuals are what the reproduction identities (sum R q = p, ...)
  // depend on, and they came out smaller than solving through the equilibrated factor.
  const Eigen::LLT<MatN> A_llt(A);
  if (!write_basis<N>(solve_gammas<N>(A_llt, m, out.work), m, d_u, d_v, out)) {
    attempt.status = MlsStatus::ill_conditioned;  // cannot happen past the rcond test; never hand out NaN anyway
    clear_result(out);
    return attempt;
  }
  out.ok = true;
  out.status = MlsStatus::ok;
  out.reason.clear();
  return attempt;
}

}  // namespace

MlsAttempt mls_solve(std::size_t m, double d_u, double d_v, const MlsSettings& settings, MlsBasis& out) {
  return settings.order >= 2 ? solve_order<6>(m, d_u, d_v, settings, out)
                             : solve_order<3>(m, d_u, d_v, settings, out);
}

void report_mls_failure(const Eigen::Vector2d& xi, const MlsAttempt& attempt, const MlsSettings& settings,
                        MlsBasis& out) {
  const std::string where = "MLS basis at (" + fmt(xi.x()) + ", " + fmt(xi.y()) + "): ";
  if (attempt.status == MlsStatus::too_few_neighbours) {
    fail(out, attempt.status,
         where + "only " + std::to_string(attempt.neighbours) + " visible control points with weight > 0 at the " +
             "maximum support factor " + fmt(settings.max_factor) + " (need " +
             std::to_string(std::max(settings.min_neighbours, basis_terms(settings.order))) + ")");
  } else {
    fail(out, attempt.status,
         where + "moment matrix is singular or ill-conditioned at the maximum support factor " +
             fmt(settings.max_factor) + " with " + std::to_string(attempt.neighbours) +
             " support points (rcond " + fmt(attempt.rcond) + " < " + fmt(settings.min_rcond) +
             "); the visible control points may be collinear");
  }
}

}  // namespace detail

}  // namespace shellfrac::shell
