#include "nurbs/degree_elevation.hpp"

#include <Eigen/QR>
#include <cmath>
#include <string>

#include "nurbs/detail.hpp"
#include "nurbs/knot_insertion.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

namespace {

double binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double b = 1.0;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

bool clamped(const KnotVector& kv) {
  const int p = kv.degree();
  const std::vector<double>& k = kv.knots();
  for (int i = 1; i <= p; ++i)
    if (k[static_cast<size_t>(i)] != k.front() || k[k.size() - 1 - static_cast<size_t>(i)] != k.back()) return false;
  return true;
}

// Knot insertion as a dense homogeneous matrix (rows: refined basis, columns: the given basis).
Eigen::MatrixXd insertion(const KnotVector& kv, const std::vector<double>& insert) {
  const CurveRefinement r = refine_knots(kv, std::vector<double>(static_cast<size_t>(kv.num_basis()), 1.0), insert);
  return Eigen::MatrixXd(r.A);
}

// Inserts each breakpoint until its multiplicity is `target` (Bezier extraction for target = degree).
std::vector<double> up_to_multiplicity(const KnotVector& kv, int target) {
  std::vector<double> insert;
  for (double x : kv.interior_breakpoints())
    for (int m = kv.multiplicity(x); m < target; ++m) insert.push_back(x);
  return insert;
}

// The knots of degree p + t with every breakpoint's multiplicity raised by t (ends: p + t + 1).
KnotVector elevated_knots(const KnotVector& kv, int t) {
  std::vector<double> knots;
  const std::vector<double>& k = kv.knots();
  for (size_t i = 0; i < k.size(); ++i) {
    knots.push_back(k[i]);
    if (i + 1 == k.size() || k[i + 1] != k[i]) knots.insert(knots.end(), static_cast<size_t>(t), k[i]);
  }
  return KnotVector(std::move(knots), kv.degree() + t);
}

}  // namespace

DegreeElevation elevate_degree(const KnotVector& kv, int t) {
  const int p = kv.degree(), n = kv.num_basis();
  if (t < 0) throw NurbsError("degree elevation by " + std::to_string(t) + ": t must be >= 0");
  if (!clamped(kv))
    throw NurbsError("degree elevation needs a clamped (open) knot vector: its first and last " + std::to_string(p + 1) +
                     " knots must be equal");
  if (t == 0) return {kv, Eigen::MatrixXd::Identity(n, n)};
  // 1. Bezier extraction: every breakpoint to multiplicity p. The segments share their end points.
  const std::vector<double> extract = up_to_multiplicity(kv, p);
  const Eigen::MatrixXd X = extract.empty() ? Eigen::MatrixXd(Eigen::MatrixXd::Identity(n, n)) : insertion(kv, extract);
  const int segments = static_cast<int>(kv.interior_breakpoints().size()) + 1;
  // 2. Each Bezier segment at degree p + t: Q_i = sum_j C(p, j) C(t, i - j) / C(p + t, i) P_j
  // (P&T Eq. 5.36).
  const int q = p + t;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(q * segments + 1, p * segments + 1);
  for (int s = 0; s < segments; ++s)
    for (int i = 0; i <= q; ++i)
      for (int j = std::max(0, i - t); j <= std::min(p, i); ++j)
        B(s * q + i, s * p + j) = binomial(p, j) * binomial(t, i - j) / binomial(q, i);
  // 3. Back from the elevated Bezier form to the elevated knots, whose insertion R (up to multiplicity
  // q) maps onto that form: R E = B X, solved exactly since B X lies in the range of R.
  DegreeElevation out{elevated_knots(kv, t), Eigen::MatrixXd()};
  const std::vector<double> back = up_to_multiplicity(out.knots, q);
  const int n_new = out.knots.num_basis();
  const Eigen::MatrixXd R = back.empty() ? Eigen::MatrixXd(Eigen::MatrixXd::Identity(n_new, n_new)) : insertion(out.knots, back);
  const Eigen::MatrixXd BX = B * X;
  out.E = R.colPivHouseholderQr().solve(BX);
  const double residual = (R * out.E - BX).cwiseAbs().maxCoeff();
  if (!(residual <= 1e-12))
    throw NurbsError("degree elevation is not exact on this knot vector (residual " + detail::format_number(residual) + ")");
  return out;
}

namespace {

// Homogeneous control points (w x, w y, w z, w) as the rows of a matrix.
Eigen::MatrixXd homogeneous(const Vec3List& points, const std::vector<double>& weights) {
  Eigen::MatrixXd h(static_cast<Eigen::Index>(points.size()), 4);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    h.block<1, 3>(r, 0) = weights[i] * points[i].transpose();
    h(r, 3) = weights[i];
  }
  return h;
}

void cartesian(const Eigen::MatrixXd& h, Vec3List& points, std::vector<double>& weights) {
  points.resize(static_cast<size_t>(h.rows()));
  weights.resize(static_cast<size_t>(h.rows()));
  for (Eigen::Index r = 0; r < h.rows(); ++r) {
    weights[static_cast<size_t>(r)] = h(r, 3);
    points[static_cast<size_t>(r)] = h.block<1, 3>(r, 0).transpose() / h(r, 3);
  }
}

}  // namespace

NurbsCurve elevate_degree(const NurbsCurve& curve, int t) {
  const DegreeElevation e = elevate_degree(curve.knots(), t);
  Vec3List points;
  std::vector<double> weights;
  cartesian(e.E * homogeneous(curve.control_points(), curve.weights()), points, weights);
  return NurbsCurve(e.knots, std::move(points), std::move(weights));
}

NurbsSurface elevate_degree(const NurbsSurface& s, int tu, int tv) {
  const DegreeElevation eu = elevate_degree(s.knots_u(), tu), ev = elevate_degree(s.knots_v(), tv);
  const int nu = s.num_u(), nv = s.num_v(), mu = eu.knots.num_basis(), mv = ev.knots.num_basis();
  const Eigen::MatrixXd h = homogeneous(s.control_points(), s.weights());  // row i + nu j
  // Along u for every row j, then along v for every new column i.
  Eigen::MatrixXd hu(mu * nv, 4);
  for (int j = 0; j < nv; ++j) hu.middleRows(j * mu, mu) = eu.E * h.middleRows(j * nu, nu);
  Eigen::MatrixXd out(mu * mv, 4);
  for (int i = 0; i < mu; ++i) {
    Eigen::MatrixXd column(nv, 4);
    for (int j = 0; j < nv; ++j) column.row(j) = hu.row(i + mu * j);
    const Eigen::MatrixXd elevated = ev.E * column;
    for (int j = 0; j < mv; ++j) out.row(i + mu * j) = elevated.row(j);
  }
  Vec3List points;
  std::vector<double> weights;
  cartesian(out, points, weights);
  return NurbsSurface(eu.knots, ev.knots, std::move(points), std::move(weights));
}

}  // namespace shellfrac::nurbs
