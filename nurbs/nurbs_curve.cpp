#include "nurbs/nurbs_curve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "nurbs/bspline_basis.hpp"
#include "nurbs/detail.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

using detail::format_number;

namespace {

constexpr std::size_t kStackBasis = 3 * (static_cast<std::size_t>(kStackDegree) + 1);

// Weighted sums of the control points and weights with the basis derivatives of order 0..order:
// homogeneous[k] = sum_i N_i^(k) w_i P_i and weight[k] = sum_i N_i^(k) w_i.
struct HomogeneousSums {
  Vec3 point[3];
  double weight[3];
};

HomogeneousSums weighted_sums(const NurbsCurve& curve, double u, int order) {
  const KnotVector& kv = curve.knots();
  const int p = kv.degree();
  const std::size_t P = static_cast<std::size_t>(p) + 1;
  detail::ScratchBuffer<kStackBasis> basis((static_cast<std::size_t>(order) + 1) * P);
  const int span = bspline_basis_derivs(kv, u, order, basis.data());

  HomogeneousSums sums;
  for (int k = 0; k <= order; ++k) {
    sums.point[k].setZero();
    sums.weight[k] = 0.0;
  }
  for (int j = 0; j <= p; ++j) {
    const std::size_t idx = static_cast<std::size_t>(span - p + j);
    const double w = curve.weights()[idx];
    const Vec3 wp = w * curve.control_points()[idx];
    for (int k = 0; k <= order; ++k) {
      const double n = basis.data()[static_cast<std::size_t>(k) * P + static_cast<std::size_t>(j)];
      sums.point[k] += n * wp;
      sums.weight[k] += n * w;
    }
  }
  return sums;
}

}  // namespace

NurbsCurve::NurbsCurve(KnotVector knots, Vec3List control_points, std::vector<double> weights)
    : knots_(std::move(knots)), control_points_(std::move(control_points)), weights_(std::move(weights)) {
  const std::size_t n = static_cast<std::size_t>(knots_.num_basis());
  if (control_points_.size() != n) {
    throw NurbsError("curve has " + std::to_string(control_points_.size()) + " control points but its knot vector (" +
                     std::to_string(knots_.size()) + " knots, degree " + std::to_string(knots_.degree()) +
                     ") requires " + std::to_string(n));
  }
  if (weights_.size() != n) {
    throw NurbsError("curve has " + std::to_string(weights_.size()) + " weights but " + std::to_string(n) +
                     " control points; give one weight per control point");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(weights_[i]) || !(weights_[i] > 0.0)) {
      throw NurbsError("weight[" + std::to_string(i) + "] = " + format_number(weights_[i]) +
                       " is invalid; weights must be finite and > 0");
    }
    if (!control_points_[i].allFinite()) {
      throw NurbsError("control point[" + std::to_string(i) + "] is not finite; coordinates must be finite numbers");
    }
  }
}

Vec3 NurbsCurve::point(double u) const {
  const HomogeneousSums s = weighted_sums(*this, u, 0);
  return s.point[0] / s.weight[0];
}

CurvePoint NurbsCurve::evaluate(double u) const {
  // Quotient rule on C = A / W with A = sum N_i w_i P_i and W = sum N_i w_i.
  const HomogeneousSums s = weighted_sums(*this, u, 2);
  const double w = s.weight[0];
  CurvePoint c;
  c.x = s.point[0] / w;
  c.dx = (s.point[1] - s.weight[1] * c.x) / w;
  c.ddx = (s.point[2] - 2.0 * s.weight[1] * c.dx - s.weight[2] * c.x) / w;
  return c;
}

NurbsCurve circular_arc(double radius, double start, double sweep) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kTwoPi = 2.0 * kPi;
  if (!std::isfinite(radius) || !(radius > 0.0)) {
    throw NurbsError("arc radius " + format_number(radius) + " is invalid; it must be finite and > 0");
  }
  if (!std::isfinite(start)) {
    throw NurbsError("arc start angle " + format_number(start) + " is invalid; it must be a finite number (radians)");
  }
  if (!std::isfinite(sweep) || !(sweep > 0.0) || sweep > kTwoPi * (1.0 + 1e-12)) {
    throw NurbsError("arc sweep " + format_number(sweep) + " is invalid; it must satisfy 0 < sweep <= 2*pi (radians)");
  }
  sweep = std::min(sweep, kTwoPi);

  // Number of pieces of at most 90 degrees; the small guard keeps pi/2 at 1 piece and 2*pi at 4.
  const int pieces = std::clamp(static_cast<int>(std::ceil(sweep / (0.5 * kPi) - 1e-10)), 1, 4);
  const double piece_angle = sweep / pieces;
  const double half = 0.5 * piece_angle;
  const double mid_weight = std::cos(half);
  const double mid_radius = radius / mid_weight;

  Vec3List points;
  std::vector<double> weights;
  points.reserve(static_cast<std::size_t>(2 * pieces + 1));
  weights.reserve(static_cast<std::size_t>(2 * pieces + 1));
  auto on_circle = [](double r, double angle) { return Vec3(r * std::cos(angle), r * std::sin(angle), 0.0); };
  points.push_back(on_circle(radius, start));
  weights.push_back(1.0);
  for (int k = 0; k < pieces; ++k) {
    const double a0 = start + k * piece_angle;
    points.push_back(on_circle(mid_radius, a0 + half));
    weights.push_back(mid_weight);
    points.push_back(on_circle(radius, start + (k + 1) * piece_angle));
    weights.push_back(1.0);
  }
  if (sweep == kTwoPi) points.back() = points.front();  // close the full circle exactly

  std::vector<double> knots = {0.0, 0.0, 0.0};
  for (int k = 1; k < pieces; ++k) {
    const double joint = static_cast<double>(k) / pieces;
    knots.push_back(joint);
    knots.push_back(joint);
  }
  knots.insert(knots.end(), {1.0, 1.0, 1.0});
  return NurbsCurve(KnotVector(std::move(knots), 2), std::move(points), std::move(weights));
}

}  // namespace shellfrac::nurbs
