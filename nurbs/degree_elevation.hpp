#pragma once
// Degree elevation of B-spline and NURBS curves and surfaces (Piegl & Tiller, The NURBS Book, sec. 5.5).
// The geometry is unchanged: every distinct interior knot's multiplicity grows by the same t as the
// degree, so the continuity across it is kept. Followed by knot insertion this is k-refinement: elevate a
// coarse patch first, then insert the cells' knots, and the splines are C^(p-1) across the new knots.
#include <Eigen/Core>

#include "nurbs/knot_vector.hpp"
#include "nurbs/nurbs_curve.hpp"
#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::nurbs {

// The elevated knot vector and the linear map of homogeneous control points (w x, w y, w z, w):
// Pw_new = E Pw_old, E of size n_new x n_old. Computed by Bezier extraction (knot insertion up to
// multiplicity p), elevation of each Bezier segment, and the exact least-squares inverse of the knot
// insertion from the elevated knot vector back to the Bezier form (its residual is checked: NurbsError
// if the map is not exact to 1e-12). Needs a clamped (open) knot vector and t >= 0.
struct DegreeElevation {
  KnotVector knots;
  Eigen::MatrixXd E;
};
DegreeElevation elevate_degree(const KnotVector& kv, int t);

// The same curve at degree p + t.
NurbsCurve elevate_degree(const NurbsCurve& curve, int t);

// The same surface at degrees (p + tu, q + tv).
NurbsSurface elevate_degree(const NurbsSurface& surface, int tu, int tv);

}  // namespace shellfrac::nurbs
