#pragma once
#include <vector>

#include "nurbs/nurbs_curve.hpp"

namespace shellfrac::coupling {

// Arc length of a NURBS curve as a function of its parameter, and its inverse. Each knot span is split
// into equal pieces integrated with Gauss-Legendre quadrature; the inverse uses bracketed Newton steps.
// Accurate to roundoff for the smooth speeds |C'(t)| of polynomial and rational spans.
// Keeps a reference to `curve`, which must outlive it.
class ArcLength {
 public:
  explicit ArcLength(const nurbs::NurbsCurve& curve, int pieces_per_span = 8);

  double total() const { return cumulative_.back(); }
  double length_to(double t) const;       // arc length from the domain start to parameter t
  double parameter_at(double s) const;    // parameter where the arc length reaches s (clamped to [0, total])

 private:
  double speed(double t) const;
  double integrate(double a, double b) const;
  int piece_of(double t) const;

  const nurbs::NurbsCurve& curve_;
  std::vector<double> nodes_;       // piece boundaries in the parameter
  std::vector<double> cumulative_;  // arc length at each node
};

}  // namespace shellfrac::coupling
