#pragma once
#include <cmath>

#include "brittle/solid_grid.hpp"

namespace shellfrac::brittle {

// Quadratic B-spline weights of a point on its 3 x 3 x 3 node stencil (thesis Eq. 2.10) and the offsets
// x_i - x_p per axis. Shared by the grid transfers and the phase-field system, so both see the same
// weights.
struct Stencil {
  int base[3];
  double w[3][3];
  double d[3][3];
};

inline Stencil make_stencil(const GVec3& x, double inv_dx, double dx) {
  Stencil s;
  for (int a = 0; a < 3; ++a) {
    const double q = x[a] * inv_dx;
    const int b = static_cast<int>(std::floor(q - 0.5));
    const double f = q - b;  // in [0.5, 1.5)
    s.base[a] = b;
    s.w[a][0] = 0.5 * (1.5 - f) * (1.5 - f);
    s.w[a][1] = 0.75 - (f - 1.0) * (f - 1.0);
    s.w[a][2] = 0.5 * (f - 0.5) * (f - 0.5);
    s.d[a][0] = -f * dx;
    s.d[a][1] = (1.0 - f) * dx;
    s.d[a][2] = (2.0 - f) * dx;
  }
  return s;
}

}  // namespace shellfrac::brittle
