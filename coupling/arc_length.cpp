#include "coupling/arc_length.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace shellfrac::coupling {

namespace {

// 8-point Gauss-Legendre rule on [-1, 1] (nodes symmetric about 0).
constexpr std::array<double, 4> kGaussX = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                           0.9602898564975363};
constexpr std::array<double, 4> kGaussW = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                           0.1012285362903763};

}  // namespace

ArcLength::ArcLength(const nurbs::NurbsCurve& curve, int pieces_per_span) : curve_(curve) {
  const nurbs::KnotVector& kv = curve.knots();
  std::vector<double> breaks = {kv.domain_begin()};
  for (double b : kv.interior_breakpoints()) breaks.push_back(b);
  breaks.push_back(kv.domain_end());
  const int pieces = std::max(1, pieces_per_span);
  for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
    for (int k = 0; k < pieces; ++k) nodes_.push_back(breaks[s] + (breaks[s + 1] - breaks[s]) * k / pieces);
  }
  nodes_.push_back(breaks.back());
  cumulative_.assign(nodes_.size(), 0.0);
  for (std::size_t i = 1; i < nodes_.size(); ++i) {
    cumulative_[i] = cumulative_[i - 1] + integrate(nodes_[i - 1], nodes_[i]);
  }
}

double ArcLength::speed(double t) const { return curve_.evaluate(t).dx.norm(); }

double ArcLength::integrate(double a, double b) const {
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  double sum = 0.0;
  for (std::size_t k = 0; k < kGaussX.size(); ++k) {
    sum += kGaussW[k] * (speed(mid - half * kGaussX[k]) + speed(mid + half * kGaussX[k]));
  }
  return half * sum;
}

int ArcLength::piece_of(double t) const {
  const auto it = std::upper_bound(nodes_.begin(), nodes_.end(), t);
  const int i = static_cast<int>(it - nodes_.begin()) - 1;
  return std::clamp(i, 0, static_cast<int>(nodes_.size()) - 2);
}

double ArcLength::length_to(double t) const {
  t = std::clamp(t, nodes_.front(), nodes_.back());
  const int i = piece_of(t);
  return cumulative_[static_cast<std::size_t>(i)] + integrate(nodes_[static_cast<std::size_t>(i)], t);
}

double ArcLength::parameter_at(double s) const {
  s = std::clamp(s, 0.0, total());
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  const std::size_t i = static_cast<std::size_t>(
      std::clamp(static_cast<int>(it - cumulative_.begin()) - 1, 0, static_cast<int>(nodes_.size()) - 2));
  double lo = nodes_[i], hi = nodes_[i + 1];
  const double piece = cumulative_[i + 1] - cumulative_[i];
  if (!(piece > 0.0)) return lo;  // degenerate (zero-speed) piece
  double t = lo + (hi - lo) * (s - cumulative_[i]) / piece;
  const double tol = 1e-15 * std::max(total(), 1e-300);
  for (int iter = 0; iter < 60; ++iter) {
    const double f = cumulative_[i] + integrate(nodes_[i], t) - s;
    if (std::abs(f) <= tol) break;
    if (f > 0.0) hi = t; else lo = t;
    const double v = speed(t);
    double next = v > 0.0 ? t - f / v : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (next == t) break;
    t = next;
  }
  return t;
}

}  // namespace shellfrac::coupling
