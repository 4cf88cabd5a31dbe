#include "shell/material_state.hpp"

#include <cstring>

namespace shellfrac::shell {

bool PointMaterialState::fully_damaged(size_t q, size_t layers) const {
  for (size_t l = 0; l < layers; ++l)
    if (damage_history[q * layers + l] >= 1.0) return true;
  return false;
}

size_t PointMaterialState::count_fully_damaged(size_t points, size_t layers) const {
  // Most calls find nothing fully damaged: a pass two values at a time (GCC leaves the scalar form of
  // this loop unvectorised) settles that before the per-point count.
  typedef double Pair __attribute__((vector_size(2 * sizeof(double))));
  typedef long long PairMask __attribute__((vector_size(2 * sizeof(long long))));
  const Pair one = {1.0, 1.0};
  PairMask reached = {0, 0};
  const size_t n = damage_history.size();
  size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    Pair h;
    std::memcpy(&h, &damage_history[i], sizeof(Pair));
    reached |= h >= one;
  }
  bool any = reached[0] || reached[1];
  for (; i < n; ++i) any = any || damage_history[i] >= 1.0;
  if (!any) return 0;
  size_t count = 0;
  for (size_t q = 0; q < points; ++q) count += fully_damaged(q, layers);
  return count;
}

}  // namespace shellfrac::shell
