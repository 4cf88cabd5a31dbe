#include "nurbs/knot_vector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "nurbs/detail.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

using detail::format_number;

namespace {

std::string knot_label(size_t i) { return "knot[" + std::to_string(i) + "]"; }

}  // namespace

KnotVector::KnotVector(std::vector<double> knots, int degree) : knots_(std::move(knots)), degree_(degree) {
  if (degree_ < 1) {
    throw NurbsError("degree must be at least 1, got " + std::to_string(degree_));
  }
  const size_t p = static_cast<size_t>(degree_);
  const size_t min_knots = 2 * (p + 1);
  if (knots_.size() < min_knots) {
    throw NurbsError("knot vector has " + std::to_string(knots_.size()) + " knots but degree " +
                     std::to_string(degree_) + " needs at least 2(p+1) = " + std::to_string(min_knots));
  }
  for (size_t i = 0; i < knots_.size(); ++i) {
    if (!std::isfinite(knots_[i])) {
      throw NurbsError(knot_label(i) + " = " + format_number(knots_[i]) + " is not finite; knots must be finite numbers");
    }
  }
  for (size_t i = 1; i < knots_.size(); ++i) {
    if (knots_[i] < knots_[i - 1]) {
      throw NurbsError("knot vector is not non-decreasing: " + knot_label(i) + " = " + format_number(knots_[i]) +
                       " < " + knot_label(i - 1) + " = " + format_number(knots_[i - 1]));
    }
  }
  const double lo = domain_begin();
  const double hi = domain_end();
  if (!(lo < hi)) {
    throw NurbsError("knot vector has an empty domain: knot[p] = " + format_number(lo) + " equals knot[n] = " +
                     format_number(hi) + " (p = " + std::to_string(degree_) + ", n = " +
                     std::to_string(num_basis()) + "); the domain must have positive length");
  }
  // Multiplicity limits: p inside the domain (keeps the basis C0), p+1 anywhere (no zero basis function).
  for (size_t i = 0; i < knots_.size();) {
    size_t j = i;
    while (j < knots_.size() && knots_[j] == knots_[i]) ++j;
    const size_t mult = j - i;
    const double value = knots_[i];
    const bool interior = value > lo && value < hi;
    if (interior && mult > p) {
      throw NurbsError("interior knot " + format_number(value) + " is repeated " + std::to_string(mult) +
                       " times; at most the degree " + std::to_string(degree_) + " is allowed");
    }
    if (mult > p + 1) {
      throw NurbsError("knot " + format_number(value) + " is repeated " + std::to_string(mult) +
                       " times; at most p+1 = " + std::to_string(degree_ + 1) + " is allowed");
    }
    i = j;
  }
}

KnotVector KnotVector::open_uniform(int degree, int num_spans, double begin, double end) {
  if (degree < 1) throw NurbsError("degree must be at least 1, got " + std::to_string(degree));
  if (num_spans < 1) throw NurbsError("number of knot spans must be at least 1, got " + std::to_string(num_spans));
  if (!std::isfinite(begin) || !std::isfinite(end) || !(begin < end)) {
    throw NurbsError("knot range [" + format_number(begin) + ", " + format_number(end) +
                     "] is invalid; begin and end must be finite with begin < end");
  }
  std::vector<double> knots;
  knots.reserve(static_cast<size_t>(2 * (degree + 1) + num_spans - 1));
  knots.insert(knots.end(), static_cast<size_t>(degree + 1), begin);
  const double length = end - begin;
  for (int k = 1; k < num_spans; ++k) knots.push_back(begin + length * k / num_spans);
  knots.insert(knots.end(), static_cast<size_t>(degree + 1), end);
  return KnotVector(std::move(knots), degree);
}

int KnotVector::find_span(double u) const {
  const double lo = domain_begin();
  const double hi = domain_end();
  // Tolerance: relative 1e-12 of the domain length, plus a few ulps of the knot magnitude so that
  // round-off on domains far from the origin (e.g. [1e6, 1e6 + 1]) is clamped as well.
  const double magnitude = std::max(std::abs(lo), std::abs(hi));
  const double tol = 1e-12 * (hi - lo) + 4.0 * std::numeric_limits<double>::epsilon() * magnitude;
  if (!(u >= lo - tol && u <= hi + tol)) {
    throw NurbsError("parameter " + format_number(u) + " is outside the knot domain [" + format_number(lo) + ", " +
                     format_number(hi) + "]");
  }
  const int n = num_basis();
  if (u >= hi) {
    // Last non-empty span: skip knots repeated at the domain end.
    int span = n - 1;
    while (knots_[static_cast<size_t>(span)] == knots_[static_cast<size_t>(span + 1)]) --span;
    return span;
  }
  if (u < lo) u = lo;
  // Binary search for the largest i in [p, n-1] with knots[i] <= u; then knots[i] <= u < knots[i+1].
  // Invariant: the answer lies in [low, low + count). Written so that the compiler can use a
  // conditional move instead of an unpredictable branch.
  const double* k = knots_.data();
  int low = degree_;
  int count = n - degree_;
  while (count > 1) {
    const int half = count / 2;
    low = k[low + half] <= u ? low + half : low;
    count -= half;
  }
  return low;
}

int KnotVector::multiplicity(double u) const {
  const auto range = std::equal_range(knots_.begin(), knots_.end(), u);
  return static_cast<int>(range.second - range.first);
}

std::vector<double> KnotVector::interior_breakpoints() const {
  const double lo = domain_begin();
  const double hi = domain_end();
  std::vector<double> result;
  for (double k : knots_) {
    if (k > lo && k < hi && (result.empty() || result.back() != k)) result.push_back(k);
  }
  return result;
}

int KnotVector::num_spans() const {
  int count = 0;
  for (int i = degree_; i < num_basis(); ++i) {
    if (knots_[static_cast<size_t>(i)] < knots_[static_cast<size_t>(i + 1)]) ++count;
  }
  return count;
}

double KnotVector::greville(int i) const {
  if (i < 0 || i >= num_basis()) {
    throw NurbsError("basis function index " + std::to_string(i) + " is out of range; valid indices are 0 .. " +
                     std::to_string(num_basis() - 1));
  }
  double sum = 0.0;
  for (int k = i + 1; k <= i + degree_; ++k) sum += knots_[static_cast<size_t>(k)];
  return sum / degree_;
}

}  // namespace shellfrac::nurbs
