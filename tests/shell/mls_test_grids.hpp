#pragma once
// Control grids and a slit shared by the MLS basis tests.
#include <Eigen/Core>

#include "nurbs/patch_builders.hpp"
#include "shell/mls_basis.hpp"

namespace shellfrac::shell::test {

// Control grid of an open quadratic knot vector on [0, 1]: Greville points 0, l/2, 3l/2, ..., 1.
inline ControlGrid quadratic_grid(int cells_u, int cells_v) {
  return ControlGrid::from_surface(nurbs::flat_patch(1.0, 1.0, cells_u, cells_v));
}

// Visibility blocked by the slit {u = 0.5, 0 <= v < 0.5} (independent of the code under test).
inline bool slit_visible(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double fa = a.x() - 0.5, fb = b.x() - 0.5;
  if (fa * fb >= 0.0) return true;  // both on one side (no grid point lies on u = 0.5)
  const double t = fa / (fa - fb);
  const double v = a.y() + t * (b.y() - a.y());
  return !(v >= 0.0 && v < 0.5);
}

}  // namespace shellfrac::shell::test
