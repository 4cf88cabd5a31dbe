#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "nurbs/knot_vector.hpp"

namespace shellfrac::nurbs {

using Vec3 = Eigen::Vector3d;
using Vec3List = std::vector<Vec3, Eigen::aligned_allocator<Vec3>>;

// Position and first/second parametric derivatives of a curve point.
struct CurvePoint {
  Vec3 x, dx, ddx;
};

// A rational B-spline curve C(u) = sum_i R_i(u) P_i with R_i = N_i w_i / sum_j N_j w_j.
// Weights must be finite and > 0. A polynomial curve has all weights 1.
class NurbsCurve {
 public:
  NurbsCurve(KnotVector knots, Vec3List control_points, std::vector<double> weights);

  const KnotVector& knots() const { return knots_; }
  const Vec3List& control_points() const { return control_points_; }
  const std::vector<double>& weights() const { return weights_; }
  int degree() const { return knots_.degree(); }

  Vec3 point(double u) const;
  CurvePoint evaluate(double u) const;  // position, first and second derivative

 private:
  KnotVector knots_;
  Vec3List control_points_;
  std::vector<double> weights_;
};

// An exact circular arc as a quadratic rational curve, centred at the origin in the xy-plane,
// from angle start to start+sweep (radians, 0 < sweep <= 2*pi). The arc is split into
// ceil(sweep / (pi/2)) equal pieces joined at double knots; knots run over [0, 1].
NurbsCurve circular_arc(double radius, double start, double sweep);

}  // namespace shellfrac::nurbs
