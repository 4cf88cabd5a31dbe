#pragma once
#include "nurbs/knot_vector.hpp"

namespace shellfrac::nurbs {

// Largest degree evaluated without heap allocation; higher degrees still work (with a scratch vector).
inline constexpr int kStackDegree = 8;

// Values and derivatives of the p+1 non-zero B-spline basis functions at u (Cox–de Boor,
// thesis Eq. 2.32–2.35), all at once.
//   span     : from KnotVector::find_span(u); the non-zero functions are N_{span-p} .. N_{span}
//   max_deriv: highest derivative wanted (0, 1, 2, ...); derivatives above p are zero
//   out      : row-major (max_deriv+1) x (p+1); out[k*(p+1)+j] = d^k N_{span-p+j} / du^k
void bspline_basis_derivs(const KnotVector& kv, int span, double u, int max_deriv, double* out);

// Convenience: finds the span and evaluates; returns the span.
int bspline_basis_derivs(const KnotVector& kv, double u, int max_deriv, double* out);

}  // namespace shellfrac::nurbs
