#pragma once
// Shared set-up of the shell tests.
#include <algorithm>
#include <cmath>
#include <vector>

#include "shell/shell_patch.hpp"

namespace shellfrac::shell::test {

inline ShellMaterial material(double E, double nu, double thickness, TransverseModel model = TransverseModel::Condensed) {
  ShellMaterial m;
  m.mu = E / (2 * (1 + nu));
  m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  m.density = 500;
  m.thickness = thickness;
  m.transverse = model;
  return m;
}

inline double max_norm(const std::vector<Vec3>& f) {
  double m = 0;
  for (const auto& v : f) m = std::max(m, v.norm());
  return m;
}

// Largest difference between `force` and minus the central-difference energy gradient, over every
// `stride`-th control point, in the first `components` coordinates (x, y, z).
inline double energy_gradient_mismatch(ShellPatch& p, const std::vector<Vec3>& force, size_t stride,
                                       int components = 3) {
  double worst = 0;
  for (size_t i = 0; i < p.x.size(); i += stride)
    for (int c = 0; c < components; ++c) {
      const double h = 1e-6, x0 = p.x[i][c];
      p.x[i][c] = x0 + h;
      const double ep = p.elastic_energy();
      p.x[i][c] = x0 - h;
      const double em = p.elastic_energy();
      p.x[i][c] = x0;
      worst = std::max(worst, std::abs(-(ep - em) / (2 * h) - force[i][c]));
    }
  return worst;
}

}  // namespace shellfrac::shell::test
