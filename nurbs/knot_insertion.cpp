#include "nurbs/knot_insertion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "nurbs/detail.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

using detail::format_number;

namespace {

using Triplet = Eigen::Triplet<double>;

// One row of the insertion matrix A: a contiguous band of columns first .. first+values.size()-1.
// Every row of a knot-insertion product is such a band, so this stays small and exact.
struct BandRow {
  int first = 0;
  std::vector<double> values;
};

// alpha * a + (1 - alpha) * b as a band row (thesis Eq. D.6/D.7 applied to rows of A).
BandRow blend(double alpha, const BandRow& a, const BandRow& b) {
  const int a_last = a.first + static_cast<int>(a.values.size());
  const int b_last = b.first + static_cast<int>(b.values.size());
  BandRow r;
  r.first = std::min(a.first, b.first);
  r.values.assign(static_cast<std::size_t>(std::max(a_last, b_last) - r.first), 0.0);
  for (std::size_t c = 0; c < a.values.size(); ++c) {
    r.values[static_cast<std::size_t>(a.first - r.first) + c] += alpha * a.values[c];
  }
  for (std::size_t c = 0; c < b.values.size(); ++c) {
    r.values[static_cast<std::size_t>(b.first - r.first) + c] += (1.0 - alpha) * b.values[c];
  }
  return r;
}

void check_weights(const std::vector<double>& weights, int expected) {
  if (weights.size() != static_cast<std::size_t>(expected)) {
    throw NurbsError("knot insertion got " + std::to_string(weights.size()) + " weights but the knot vector has " +
                     std::to_string(expected) + " basis functions; give one weight per basis function");
  }
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i]) || !(weights[i] > 0.0)) {
      throw NurbsError("weight[" + std::to_string(i) + "] = " + format_number(weights[i]) +
                       " is invalid; weights must be finite and > 0");
    }
  }
}

bool all_equal(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [&](double x) { return x == values.front(); });
}

// U = diag(1/w_new) A diag(w), from the triplets of A; fills w_new = A w (thesis Eq. D.8–D.10).
// When all old weights are equal (e.g. a polynomial patch) the weights are kept exactly and U = A.
SparseMatrix rational_refinement(const std::vector<Triplet>& a_entries, int rows, int cols,
                                 const std::vector<double>& weights, std::vector<double>& new_weights) {
  SparseMatrix U(rows, cols);
  if (all_equal(weights)) {
    new_weights.assign(static_cast<std::size_t>(rows), weights.front());
    U.setFromTriplets(a_entries.begin(), a_entries.end());
    return U;
  }
  new_weights.assign(static_cast<std::size_t>(rows), 0.0);
  for (const Triplet& t : a_entries) {
    new_weights[static_cast<std::size_t>(t.row())] += t.value() * weights[static_cast<std::size_t>(t.col())];
  }
  std::vector<Triplet> u_entries;
  u_entries.reserve(a_entries.size());
  for (const Triplet& t : a_entries) {
    u_entries.emplace_back(t.row(), t.col(),
                           t.value() * weights[static_cast<std::size_t>(t.col())] /
                               new_weights[static_cast<std::size_t>(t.row())]);
  }
  U.setFromTriplets(u_entries.begin(), u_entries.end());
  return U;
}

std::vector<Triplet> triplets_of(const SparseMatrix& m) {
  std::vector<Triplet> t;
  t.reserve(static_cast<std::size_t>(m.nonZeros()));
  for (int r = 0; r < m.outerSize(); ++r) {
    for (SparseMatrix::InnerIterator it(m, r); it; ++it) t.emplace_back(r, static_cast<int>(it.col()), it.value());
  }
  return t;
}

Vec3List refined_points(const SparseMatrix& U, const Vec3List& points) {
  Vec3List result(static_cast<std::size_t>(U.rows()), Vec3::Zero());
  for (int r = 0; r < U.outerSize(); ++r) {
    for (SparseMatrix::InnerIterator it(U, r); it; ++it) {
      result[static_cast<std::size_t>(r)] += it.value() * points[static_cast<std::size_t>(it.col())];
    }
  }
  return result;
}

}  // namespace

CurveRefinement refine_knots(const KnotVector& kv, const std::vector<double>& weights,
                             const std::vector<double>& insert) {
  const int p = kv.degree();
  const int n = kv.num_basis();
  check_weights(weights, n);

  const double lo = kv.domain_begin();
  const double hi = kv.domain_end();
  for (double x : insert) {  // checked before sorting: NaN would break the sort's ordering
    if (!(x >= lo && x <= hi)) {
      throw NurbsError("knot to insert " + format_number(x) + " is outside the knot domain [" + format_number(lo) +
                       ", " + format_number(hi) + "]");
    }
  }
  std::vector<double> sorted = insert;
  std::sort(sorted.begin(), sorted.end());

  // A starts as the identity; each insertion replaces rows by affine blends of neighbouring rows.
  std::vector<BandRow> rows(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = BandRow{i, {1.0}};

  KnotVector current = kv;
  for (double x : sorted) {
    const int mult = current.multiplicity(x) + 1;
    if (mult > p) {
      throw NurbsError("inserting knot " + format_number(x) + " would raise its multiplicity to " +
                       std::to_string(mult) + "; the degree " + std::to_string(p) + " allows at most " +
                       std::to_string(p));
    }
    const int k = current.find_span(x);  // knots[k] <= x <= knots[k+1], non-empty span
    const std::vector<double>& U = current.knots();
    std::vector<BandRow> next;
    next.reserve(rows.size() + 1);
    for (int i = 0; i <= k - p; ++i) next.push_back(rows[static_cast<std::size_t>(i)]);
    for (int i = k - p + 1; i <= k; ++i) {
      const double ui = U[static_cast<std::size_t>(i)];
      const double alpha = (x - ui) / (U[static_cast<std::size_t>(i + p)] - ui);  // thesis Eq. D.7
      next.push_back(blend(alpha, rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(i - 1)]));
    }
    for (std::size_t i = static_cast<std::size_t>(k); i < rows.size(); ++i) next.push_back(std::move(rows[i]));
    rows = std::move(next);

    std::vector<double> knots = U;
    knots.insert(knots.begin() + (k + 1), x);
    current = KnotVector(std::move(knots), p);
  }

  const int new_n = static_cast<int>(rows.size());
  std::vector<Triplet> a_entries;
  for (int r = 0; r < new_n; ++r) {
    const BandRow& row = rows[static_cast<std::size_t>(r)];
    for (std::size_t c = 0; c < row.values.size(); ++c) {
      if (row.values[c] != 0.0) a_entries.emplace_back(r, row.first + static_cast<int>(c), row.values[c]);
    }
  }
  CurveRefinement result{current, SparseMatrix(new_n, n), SparseMatrix(), {}};
  result.A.setFromTriplets(a_entries.begin(), a_entries.end());
  result.U = rational_refinement(a_entries, new_n, n, weights, result.weights);
  return result;
}

NurbsCurve insert_knots(const NurbsCurve& curve, const std::vector<double>& insert) {
  CurveRefinement r = refine_knots(curve.knots(), curve.weights(), insert);
  return NurbsCurve(std::move(r.knots), refined_points(r.U, curve.control_points()), std::move(r.weights));
}

SurfaceRefinement insert_knots(const NurbsSurface& surface, const std::vector<double>& insert_u,
                               const std::vector<double>& insert_v) {
  // A depends only on the knots: refine each direction with unit weights, then combine.
  const CurveRefinement ru =
      refine_knots(surface.knots_u(), std::vector<double>(static_cast<std::size_t>(surface.num_u()), 1.0), insert_u);
  const CurveRefinement rv =
      refine_knots(surface.knots_v(), std::vector<double>(static_cast<std::size_t>(surface.num_v()), 1.0), insert_v);

  // A_surface = kron(A_v, A_u) on flat indices i + nu * j.
  const int nu = surface.num_u();
  const int new_nu = static_cast<int>(ru.A.rows());
  const std::vector<Triplet> tu = triplets_of(ru.A);
  const std::vector<Triplet> tv = triplets_of(rv.A);
  std::vector<Triplet> a_entries;
  a_entries.reserve(tu.size() * tv.size());
  for (const Triplet& b : tv) {
    for (const Triplet& a : tu) {
      a_entries.emplace_back(a.row() + new_nu * b.row(), a.col() + nu * b.col(), a.value() * b.value());
    }
  }
  const int rows = new_nu * static_cast<int>(rv.A.rows());
  const int cols = nu * surface.num_v();
  std::vector<double> new_weights;
  SparseMatrix U = rational_refinement(a_entries, rows, cols, surface.weights(), new_weights);
  Vec3List points = refined_points(U, surface.control_points());
  return SurfaceRefinement{NurbsSurface(ru.knots, rv.knots, std::move(points), std::move(new_weights)), std::move(U)};
}

}  // namespace shellfrac::nurbs
