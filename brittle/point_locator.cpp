#include "brittle/point_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::brittle {

PointBuckets::PointBuckets(const std::vector<Vec3>& points, double cell_size) : cell(cell_size) {
  if (points.empty()) return;
  Vec3 hi = points.front();
  lo = hi;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (int a = 0; a < 3; ++a) dims[a] = std::max(1, static_cast<int>(std::floor((hi[a] - lo[a]) / cell)) + 1);
  const size_t buckets = static_cast<size_t>(dims.x()) * dims.y() * dims.z();
  std::vector<uint32_t> slot(points.size());
  offsets.assign(buckets + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    slot[i] = static_cast<uint32_t>(index(bucket(points[i])));
    ++offsets[slot[i] + 1];
  }
  for (size_t b = 0; b < buckets; ++b) offsets[b + 1] += offsets[b];
  items.resize(points.size());
  std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) items[cursor[slot[i]]++] = static_cast<uint32_t>(i);
}

Eigen::Vector3i PointBuckets::bucket(const Vec3& x) const {
  return ((x - lo) / cell).array().floor().cast<int>().min(dims.array() - 1).max(0);
}

PointLocator::PointLocator(const std::vector<Vec3>& points) : points_(&points) {
  if (points.empty()) return;
  Vec3 lo = points.front(), hi = lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 ext = (hi - lo).cwiseMax(1e-12 * (1.0 + hi.cwiseAbs().maxCoeff()));
  // About two points per bucket, at most 256 buckets per axis.
  buckets_ = PointBuckets(points, std::max(std::cbrt(ext.prod() / static_cast<double>(points.size()) * 2.0), ext.maxCoeff() / 256.0));
}

int PointLocator::nearest(const Vec3& x) const {
  if (!points_ || points_->empty()) return -1;
  const std::vector<Vec3>& pts = *points_;
  const PointBuckets& g = buckets_;
  const double cell = g.cell;
  const Eigen::Vector3i c = g.bucket(x);
  // Distance from x to the outside of the bucket cube of radius r around c is at least r * cell minus how
  // far x lies outside bucket c (x may be outside the grid).
  const Vec3 centre = g.lo + (c.cast<double>() + Vec3::Constant(0.5)) * cell;
  const double slack = std::max(0.0, ((x - centre).cwiseAbs().array() - 0.5 * cell).maxCoeff());
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  const int max_r = g.dims.maxCoeff();
  for (int r = 0; r <= max_r; ++r) {
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
          const Eigen::Vector3i b = c + Eigen::Vector3i(dx, dy, dz);
          if (!g.inside(b)) continue;
          const size_t k = g.index(b);
          for (uint32_t e = g.offsets[k]; e < g.offsets[k + 1]; ++e) {
            const double d = (pts[g.items[e]] - x).squaredNorm();
            if (d < best_d || (d == best_d && static_cast<int>(g.items[e]) < best)) {
              best_d = d;
              best = static_cast<int>(g.items[e]);
            }
          }
        }
    if (best >= 0 && std::sqrt(best_d) <= r * cell - slack) break;
  }
  return best;
}

}  // namespace shellfrac::brittle
