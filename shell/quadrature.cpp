#include "shell/quadrature.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace shellfrac::shell {

GaussRule gauss_legendre(int n) {
  switch (n) {
    case 1: return {{0.0}, {2.0}};
    case 2: {
      const double a = 1.0 / std::sqrt(3.0);
      return {{-a, a}, {1.0, 1.0}};
    }
    case 3: {
      const double a = std::sqrt(0.6);
      return {{-a, 0.0, a}, {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0}};
    }
    case 4: {
      const double a = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2));
      const double b = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
      const double wa = (18.0 + std::sqrt(30.0)) / 36.0, wb = (18.0 - std::sqrt(30.0)) / 36.0;
      return {{-b, -a, a, b}, {wb, wa, wa, wb}};
    }
    case 5: {
      const double a = std::sqrt(5.0 - 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
      const double b = std::sqrt(5.0 + 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
      const double wa = (322.0 + 13.0 * std::sqrt(70.0)) / 900.0;
      const double wb = (322.0 - 13.0 * std::sqrt(70.0)) / 900.0;
      return {{-b, -a, 0.0, a, b}, {wb, wa, 128.0 / 225.0, wa, wb}};
    }
    default:
      break;
  }
  if (n < 1 || n > 8) throw std::invalid_argument("quadrature points per direction must be 1..8, got " + std::to_string(n));
  // Six to eight points (degrees 5 to 7): the roots of the Legendre polynomial P_n by Newton from the
  // usual estimates, w = 2 / ((1 - x^2) P_n'(x)^2).
  GaussRule g;
  g.x.assign(static_cast<size_t>(n), 0.0);
  g.w.assign(static_cast<size_t>(n), 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;  // P_0, P_1, then the three-term recurrence up to P_n
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double step = p1 / dp;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double w = 2 / ((1 - x * x) * dp * dp);
    g.x[static_cast<size_t>(i)] = -x;
    g.x[static_cast<size_t>(n - 1 - i)] = x;
    g.w[static_cast<size_t>(i)] = g.w[static_cast<size_t>(n - 1 - i)] = w;
  }
  return g;
}

LayerRule thickness_layers(int layers, double thickness) {
  if (layers == 1) return {{0.0}, {thickness}};
  if (layers == 3)
    return {{-0.5 * thickness, 0.0, 0.5 * thickness},
            {thickness / 6.0, 4.0 * thickness / 6.0, thickness / 6.0}};
  throw std::invalid_argument("shell layers must be 1 or 3, got " + std::to_string(layers));
}

}  // namespace shellfrac::shell
