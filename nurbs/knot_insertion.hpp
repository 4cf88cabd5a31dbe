#pragma once
#include <Eigen/SparseCore>
#include <vector>

#include "nurbs/nurbs_curve.hpp"
#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::nurbs {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Result of inserting knots into one knot vector (thesis appendix D).
//   A       : homogeneous insertion matrix A = A^1 A^2 ... A^r (Eq. D.11), (n+r) x n
//   U       : refinement matrix on Cartesian control points, U = W_new^-1 A W (Eq. D.8), so Q = U P
//   weights : new weights W_new = A w
struct CurveRefinement {
  KnotVector knots;
  SparseMatrix A;
  SparseMatrix U;
  std::vector<double> weights;
};

// Inserts the knots in `insert` (any order, repeats allowed) into kv, for control weights `weights`
// (size kv.num_basis()). Each inserted value must lie inside the domain and may not raise a knot's
// multiplicity above the degree (NurbsError otherwise).
CurveRefinement refine_knots(const KnotVector& kv, const std::vector<double>& weights,
                             const std::vector<double>& insert);

// The same curve on a refined knot vector: control points Q = U P.
NurbsCurve insert_knots(const NurbsCurve& curve, const std::vector<double>& insert);

enum class Direction { U, V };

// Result of refining a surface in one or both directions: the new surface and the refinement matrix
// on flat control point indices, new_points = U * old_points (rational weights handled as in Eq. D.8).
struct SurfaceRefinement {
  NurbsSurface surface;
  SparseMatrix U;
};

SurfaceRefinement insert_knots(const NurbsSurface& surface, const std::vector<double>& insert_u,
                               const std::vector<double>& insert_v);

}  // namespace shellfrac::nurbs
