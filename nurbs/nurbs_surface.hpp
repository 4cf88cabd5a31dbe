#pragma once
#include <vector>

#include "nurbs/nurbs_curve.hpp"

namespace shellfrac::nurbs {

// Position, parametric derivatives up to second order, and unit normal of a surface point.
struct SurfacePoint {
  Vec3 x;              // S(u, v)
  Vec3 du, dv;         // first derivatives: the covariant tangents a_1, a_2 (thesis Table 4.1)
  Vec3 duu, duv, dvv;  // second derivatives
  Vec3 normal;         // a_3 = (a_1 x a_2) / |a_1 x a_2|
};

// The non-zero rational basis functions R_ij of a surface at one parameter point, with their first
// and second parametric derivatives (thesis Eq. 2.38). Buffers are reused between calls.
struct SurfaceBasis {
  int count = 0;             // (p+1)(q+1)
  std::vector<int> index;    // flat control point index of each function (i + nu * j)
  std::vector<double> R, Ru, Rv, Ruu, Ruv, Rvv;
};

// A tensor-product NURBS surface (thesis Eq. 2.37). Control point (i, j), 0 <= i < nu, 0 <= j < nv,
// is stored at flat index i + nu * j (u runs fastest). Weights must be finite and > 0.
class NurbsSurface {
 public:
  NurbsSurface(KnotVector knots_u, KnotVector knots_v, Vec3List control_points,
               std::vector<double> weights);

  const KnotVector& knots_u() const { return knots_u_; }
  const KnotVector& knots_v() const { return knots_v_; }
  int num_u() const { return knots_u_.num_basis(); }
  int num_v() const { return knots_v_.num_basis(); }
  int flat_index(int i, int j) const { return i + num_u() * j; }
  const Vec3List& control_points() const { return control_points_; }
  const std::vector<double>& weights() const { return weights_; }
  bool is_rational() const { return rational_; }

  Vec3 point(double u, double v) const;
  Vec3 normal(double u, double v) const;
  SurfacePoint evaluate(double u, double v) const;

  // Rational basis with derivatives at (u, v); writes into out (see SurfaceBasis).
  void rational_basis(double u, double v, SurfaceBasis& out) const;

 private:
  KnotVector knots_u_, knots_v_;
  Vec3List control_points_;
  std::vector<double> weights_;
  bool rational_ = false;
};

}  // namespace shellfrac::nurbs
