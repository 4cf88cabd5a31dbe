#pragma once
#include <cstddef>
#include <vector>

namespace shellfrac::nurbs {

// A validated, non-decreasing knot vector for B-splines of a given degree p (thesis sec. 2.4).
// With m+1 knots there are n = m - p basis functions; the parametric domain is [knots[p], knots[n]].
// Validation (NurbsError on failure): degree >= 1, at least 2(p+1) knots, all finite, non-decreasing,
// a non-empty domain, and no interior knot repeated more than p times (the basis stays C0 or smoother).
class KnotVector {
 public:
  KnotVector(std::vector<double> knots, int degree);

  // Open (clamped) knot vector with num_spans equal spans on [begin, end]; end knots repeated p+1 times.
  static KnotVector open_uniform(int degree, int num_spans, double begin = 0.0, double end = 1.0);

  int degree() const { return degree_; }
  int num_basis() const { return static_cast<int>(knots_.size()) - degree_ - 1; }
  int size() const { return static_cast<int>(knots_.size()); }
  const std::vector<double>& knots() const { return knots_; }
  double operator[](int i) const { return knots_[static_cast<size_t>(i)]; }

  double domain_begin() const { return knots_[static_cast<size_t>(degree_)]; }
  double domain_end() const { return knots_[static_cast<size_t>(num_basis())]; }

  // Index i of the knot span [knots[i], knots[i+1]) that contains u, with p <= i <= n-1.
  // At u == domain_end the last non-empty span is returned (not the degenerate one past it).
  // Values outside the domain by more than a relative 1e-12 throw; closer ones are clamped.
  int find_span(double u) const;

  // How many times the value u occurs (exactly) in the knot vector.
  int multiplicity(double u) const;

  // Distinct knot values inside the open domain (domain_begin, domain_end), increasing.
  std::vector<double> interior_breakpoints() const;

  // Number of non-empty spans (cells) in the domain.
  int num_spans() const;

  // Greville abscissa of basis function i: the average of knots i+1 .. i+p.
  double greville(int i) const;

 private:
  std::vector<double> knots_;
  int degree_;
};

}  // namespace shellfrac::nurbs
