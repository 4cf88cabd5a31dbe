#pragma once
// Shared set-up of the shell tests.
#include <algorithm>
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

}  // namespace shellfrac::shell::test
