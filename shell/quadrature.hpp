#pragma once
#include <vector>

namespace shellfrac::shell {

// Gauss-Legendre abscissae and weights on [-1, 1] for n = 1..5 points.
struct GaussRule {
  std::vector<double> x, w;
};
GaussRule gauss_legendre(int n);

// Through-thickness layers: 3 layers at xi3 = -tau/2, 0, +tau/2 (lower lamina, mid-surface, upper
// lamina; thesis sec. 4.3.2) with Simpson weights tau/6, 4tau/6, tau/6, which integrate the bending
// energy (quadratic in xi3) exactly; or 1 layer (the mid-surface, weight tau: membrane only).
struct LayerRule {
  std::vector<double> xi3, w;
};
LayerRule thickness_layers(int layers, double thickness);

// Type-IV quadrature sampling of a patch: a points x points stencil per cell on each layer (thesis: 4x4,
// three layers).
struct QuadratureRule {
  int points_per_direction = 4;
  int layers = 3;
};

}  // namespace shellfrac::shell
