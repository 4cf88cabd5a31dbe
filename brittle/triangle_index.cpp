#include "brittle/triangle_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::brittle {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary) {
  // Voronoi regions of the vertices, edges and face (Ericson, Real-Time Collision Detection, 5.1.5).
  auto out = [&](double u, double v, double w) {
    if (bary) *bary = Vec3(u, v, w);
    return Vec3(u * a + v * b + w * c);
  };
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return out(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return out(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return out(1 - v, v, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return out(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return out(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return out(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return out(1, 0, 0);  // degenerate triangle: its first corner
  const double v = vb / denom, w = vc / denom;
  return out(1 - v - w, v, w);
}

uint64_t TriangleIndex::key(long i, long j, long k) const {
  constexpr long off = 1L << 20;
  auto f = [](long v) { return static_cast<uint64_t>(std::clamp(v + off, 0L, (1L << 21) - 1)); };
  return (f(i) << 42) | (f(j) << 21) | f(k);
}

TriangleIndex::TriangleIndex(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, double bucket)
    : positions_(positions), triangles_(triangles), cell_(bucket), inv_cell_(1.0 / bucket) {
  normals_.resize(triangles_.size());
  std::vector<std::pair<uint64_t, uint32_t>> pairs;
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3 &a = positions_[triangles_[t][0]], &b = positions_[triangles_[t][1]], &c = positions_[triangles_[t][2]];
    const Vec3 n = (b - a).cross(c - a);
    normals_[t] = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const Eigen::Vector3i l = (lo * inv_cell_).array().floor().cast<int>(), h = (hi * inv_cell_).array().floor().cast<int>();
    for (int k = l.z(); k <= h.z(); ++k)
      for (int j = l.y(); j <= h.y(); ++j)
        for (int i = l.x(); i <= h.x(); ++i) pairs.emplace_back(key(i, j, k), static_cast<uint32_t>(t));
  }
  std::sort(pairs.begin(), pairs.end());
  for (size_t e = 0; e < pairs.size(); ++e) {
    if (e == 0 || pairs[e].first != pairs[e - 1].first) {
      keys_.push_back(pairs[e].first);
      offsets_.push_back(static_cast<uint32_t>(e));
    }
    items_.push_back(pairs[e].second);
  }
  offsets_.push_back(static_cast<uint32_t>(items_.size()));
}

TriangleIndex::Hit TriangleIndex::closest(const Vec3& x, double max_distance) const {
  Hit best;
  if (triangles_.empty()) return best;
  double best_d2 = max_distance * max_distance;
  const Eigen::Vector3i l = ((x.array() - max_distance) * inv_cell_).floor().cast<int>();
  const Eigen::Vector3i h = ((x.array() + max_distance) * inv_cell_).floor().cast<int>();
  for (int k = l.z(); k <= h.z(); ++k)
    for (int j = l.y(); j <= h.y(); ++j)
      for (int i = l.x(); i <= h.x(); ++i) {
        const auto it = std::lower_bound(keys_.begin(), keys_.end(), key(i, j, k));
        if (it == keys_.end() || *it != key(i, j, k)) continue;
        const size_t b = static_cast<size_t>(it - keys_.begin());
        for (uint32_t e = offsets_[b]; e < offsets_[b + 1]; ++e) {
          const Tri& t = triangles_[items_[e]];
          Vec3 bc;
          const Vec3 q = closest_point_on_triangle(x, positions_[t[0]], positions_[t[1]], positions_[t[2]], &bc);
          const double d2 = (q - x).squaredNorm();
          // Ties go to the lower triangle index, so the answer does not depend on bucket order.
          if (d2 < best_d2 || (best.found && d2 == best_d2 && static_cast<int>(items_[e]) < best.triangle)) {
            best_d2 = d2;
            best.found = true;
            best.point = q;
            best.triangle = static_cast<int>(items_[e]);
            best.barycentric = bc;
          }
        }
      }
  if (best.found) best.distance = std::sqrt(best_d2);
  return best;
}

}  // namespace shellfrac::brittle
