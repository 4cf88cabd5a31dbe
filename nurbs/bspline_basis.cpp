#include "nurbs/bspline_basis.hpp"

#include <algorithm>
#include <string>

#include "nurbs/detail.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

namespace {

// Scratch layout for degree p (P = p + 1):
//   table : P x P. Upper triangle incl. diagonal, table[r][j] (r <= j) = N_{span-j+r, j}(u), the
//           degree-j functions; strict lower triangle, table[j][r] (r < j) = 1 / (knots[span+r+1] -
//           knots[span+r+1-j]), the reciprocal knot difference that divides at level j. Storing the
//           reciprocal turns every later division into a multiplication. The differences are > 0
//           because every one of them covers the non-empty span [knots[span], knots[span+1]].
//   left, right : P each; left[j] = u - knots[span+1-j], right[j] = knots[span+j] - u.
//   lift : P, derivative values while they are raised from degree p-k to degree p.
constexpr std::size_t scratch_size(std::size_t P) { return P * P + 3 * P; }

constexpr std::size_t kStackP = static_cast<std::size_t>(kStackDegree) + 1;

// kDegree > 0 fixes the degree at compile time (fully unrolled loops for the common low degrees);
// kDegree == 0 takes it from p_runtime.
template <int kDegree>
void evaluate_basis(const double* knots, int p_runtime, int span, double u, int max_deriv, double* out,
                    double* scratch) {
  const int p = kDegree > 0 ? kDegree : p_runtime;
  const int P = p + 1;
  double* table = scratch;
  double* left = table + P * P;
  double* right = left + P;
  double* lift = right + P;
  auto T = [&](int row, int col) -> double& { return table[row * P + col]; };

  // Values: Cox–de Boor recursion (thesis Eq. 2.32–2.33), one degree at a time.
  T(0, 0) = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    double carry = 0.0;
    for (int r = 0; r < j; ++r) {
      T(j, r) = 1.0 / (right[r + 1] + left[j - r]);
      const double ratio = T(r, j - 1) * T(j, r);
      T(r, j) = carry + right[r + 1] * ratio;
      carry = left[j - r] * ratio;
    }
    T(j, j) = carry;
  }
  for (int j = 0; j <= p; ++j) out[j] = T(j, p);

  // Derivatives (thesis Eq. 2.34–2.35): start from the degree p-k functions (table column p-k) and
  // apply d N_{i,m} = m (N_{i,m-1} / (u_{i+m} - u_i) - N_{i+1,m-1} / (u_{i+m+1} - u_{i+1})) for
  // m = p-k+1 .. p. At degree m, entry j is function span-m+j; both denominators are in table row m.
  const int top = std::min(max_deriv, p);
  for (int k = 1; k <= top; ++k) {
    for (int j = 0; j <= p - k; ++j) lift[j] = T(j, p - k);
    for (int m = p - k + 1; m <= p; ++m) {
      // In place, from the top down: entry j reads the old entries j-1 and j.
      lift[m] = m * lift[m - 1] * T(m, m - 1);
      for (int j = m - 1; j >= 1; --j) lift[j] = m * (lift[j - 1] * T(m, j - 1) - lift[j] * T(m, j));
      lift[0] = -m * lift[0] * T(m, 0);
    }
    for (int j = 0; j <= p; ++j) out[k * P + j] = lift[j];
  }
  for (int k = top + 1; k <= max_deriv; ++k) std::fill(out + k * P, out + (k + 1) * P, 0.0);
}

}  // namespace

void bspline_basis_derivs(const KnotVector& kv, int span, double u, int max_deriv, double* out) {
  const int p = kv.degree();
  if (span < p || span >= kv.num_basis() || !(kv[span] < kv[span + 1])) {
    throw NurbsError("knot span " + std::to_string(span) + " is not a non-empty span of the knot vector; valid spans are " +
                     std::to_string(p) + " .. " + std::to_string(kv.num_basis() - 1) + " with knot[i] < knot[i+1]");
  }
  if (max_deriv < 0) {
    throw NurbsError("derivative order must be >= 0, got " + std::to_string(max_deriv));
  }
  const std::size_t P = static_cast<std::size_t>(p) + 1;
  detail::ScratchBuffer<scratch_size(kStackP)> scratch(scratch_size(P));
  const double* knots = kv.knots().data();
  switch (p) {
    case 1: evaluate_basis<1>(knots, p, span, u, max_deriv, out, scratch.data()); break;
    case 2: evaluate_basis<2>(knots, p, span, u, max_deriv, out, scratch.data()); break;
    case 3: evaluate_basis<3>(knots, p, span, u, max_deriv, out, scratch.data()); break;
    case 4: evaluate_basis<4>(knots, p, span, u, max_deriv, out, scratch.data()); break;
    default: evaluate_basis<0>(knots, p, span, u, max_deriv, out, scratch.data()); break;
  }
}

int bspline_basis_derivs(const KnotVector& kv, double u, int max_deriv, double* out) {
  const int span = kv.find_span(u);
  // find_span accepted u; evaluate at the clamped value so round-off outside the domain is harmless.
  u = std::clamp(u, kv.domain_begin(), kv.domain_end());
  bspline_basis_derivs(kv, span, u, max_deriv, out);
  return span;
}

}  // namespace shellfrac::nurbs
