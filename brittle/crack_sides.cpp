#include "brittle/crack_sides.hpp"

#include <tbb/parallel_for.h>

#include <cmath>

namespace shellfrac::brittle {

void CrackSides::clear() {
  near_.clear();
  normal_.clear();
  slot_.clear();
  mask_.clear();
}

void CrackSides::set_crack(const TriMesh& crack, const std::vector<Vec3>& rest, double radius) {
  clear();
  if (crack.triangles.empty()) return;
  const TriangleIndex index(crack.positions, crack.triangles, radius);
  const size_t n = rest.size();
  std::vector<TriangleIndex::Hit> hit(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) hit[p] = index.closest(rest[p], radius);
  });
  slot_.assign(n, -1);
  mask_.assign(n, 0);
  for (size_t p = 0; p < n; ++p) {
    if (!hit[p].found) continue;
    Vec3 d = rest[p] - hit[p].point;
    // On the surface itself the direction is undefined: use the face normal (either sign).
    const double len = d.norm();
    d = len > 1e-9 * radius ? Vec3(d / len) : index.triangle_normal(hit[p].triangle);
    slot_[p] = static_cast<int32_t>(near_.size());
    near_.push_back(static_cast<uint32_t>(p));
    normal_.push_back(d);
  }
  if (near_.empty()) clear();
}

void CrackSides::classify(const SolidGrid& grid, const Vec3* x) {
  if (!active()) return;
  best_w_.assign(grid.num_nodes(), -1.0);
  best_slot_.assign(grid.num_nodes(), -1);
  const double inv_dx = 1.0 / grid.dx();
  const Eigen::Vector3i lo = grid.lower(), dims = grid.dims();
  const long sy = dims.x(), sz = static_cast<long>(dims.x()) * dims.y();
  auto weights = [&](const Vec3& xp, double w[3][3], long& base) {
    base = 0;
    const long stride[3] = {1, sy, sz};
    for (int a = 0; a < 3; ++a) {
      const double q = xp[a] * inv_dx;
      const int b = static_cast<int>(std::floor(q - 0.5));
      const double f = q - b;
      w[a][0] = 0.5 * (1.5 - f) * (1.5 - f);
      w[a][1] = 0.75 - (f - 1.0) * (f - 1.0);
      w[a][2] = 0.5 * (f - 0.5) * (f - 0.5);
      base += (b - lo[a]) * stride[a];
    }
  };
  // 1. Reference particle of every node: the near particle with the largest weight there (the first one
  //    in scatter order on ties), a coloured scatter so that it is the same for any thread count.
  grid.for_particles_coloured([&](uint32_t p) {
    const int32_t s = slot_[p];
    if (s < 0) return;
    double w[3][3];
    long base;
    weights(x[p], w, base);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const size_t idx = static_cast<size_t>(base + i + j * sy + k * sz);
          const double wt = w[0][i] * w[1][j] * w[2][k];
          if (wt > best_w_[idx]) {
            best_w_[idx] = wt;
            best_slot_[idx] = s;
          }
        }
  });
  // 2. Field bits: clearly opposite to the node's reference particle -> field 1.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, near_.size(), 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t s = r.begin(); s != r.end(); ++s) {
      const uint32_t p = near_[s];
      double w[3][3];
      long base;
      weights(x[p], w, base);
      FieldMask m = 0;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const int32_t ref = best_slot_[static_cast<size_t>(base + i + j * sy + k * sz)];
            if (ref >= 0 && normal_[s].dot(normal_[static_cast<size_t>(ref)]) < kOppositeCosine)
              m |= FieldMask{1} << (i + 3 * j + 9 * k);
          }
      mask_[p] = m;
    }
  });
  (void)dims;
}

int CrackSides::field_at(size_t index, const Vec3& n) const {
  if (!active() || index >= best_slot_.size()) return 0;
  const int32_t ref = best_slot_[index];
  return ref >= 0 && n.dot(normal_[static_cast<size_t>(ref)]) < kOppositeCosine ? 1 : 0;
}

}  // namespace shellfrac::brittle
