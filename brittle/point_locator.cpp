#include "brittle/point_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::brittle {

PointLocator::PointLocator(const std::vector<Vec3>& points) : points_(&points) {
  if (points.empty()) return;
  Vec3 lo = points.front(), hi = lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo_ = lo;
  const Vec3 ext = (hi - lo).cwiseMax(1e-12 * (1.0 + hi.cwiseAbs().maxCoeff()));
  // About two points per bucket, at most 256 buckets per axis.
  cell_ = std::max(std::cbrt(ext.prod() / static_cast<double>(points.size()) * 2.0), ext.maxCoeff() / 256.0);
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::floor(ext[a] / cell_)) + 1);
  const size_t buckets = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
  std::vector<uint32_t> bucket(points.size());
  offsets_.assign(buckets + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3i c = ((points[i] - lo_) / cell_).array().floor().cast<int>().min(dims_.array() - 1).max(0);
    bucket[i] = static_cast<uint32_t>(c.x() + dims_.x() * (c.y() + dims_.y() * c.z()));
    ++offsets_[bucket[i] + 1];
  }
  for (size_t b = 0; b < buckets; ++b) offsets_[b + 1] += offsets_[b];
  items_.resize(points.size());
  std::vector<uint32_t> cursor(offsets_.begin(), offsets_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) items_[cursor[bucket[i]]++] = static_cast<uint32_t>(i);
}

int PointLocator::nearest(const Vec3& x) const {
  if (!points_ || points_->empty()) return -1;
  const std::vector<Vec3>& pts = *points_;
  const Eigen::Vector3i c = ((x - lo_) / cell_).array().floor().cast<int>().min(dims_.array() - 1).max(0);
  // Distance from x to the outside of the bucket cube of radius r around c is at least r * cell minus how
  // far x lies outside bucket c (x may be outside the grid).
  const Vec3 centre = lo_ + (c.cast<double>() + Vec3::Constant(0.5)) * cell_;
  const double slack = std::max(0.0, ((x - centre).cwiseAbs().array() - 0.5 * cell_).maxCoeff());
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  const int max_r = dims_.maxCoeff();
  for (int r = 0; r <= max_r; ++r) {
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
          const Eigen::Vector3i b = c + Eigen::Vector3i(dx, dy, dz);
          if ((b.array() < 0).any() || (b.array() >= dims_.array()).any()) continue;
          const size_t k = static_cast<size_t>(b.x() + dims_.x() * (b.y() + dims_.y() * b.z()));
          for (uint32_t e = offsets_[k]; e < offsets_[k + 1]; ++e) {
            const double d = (pts[items_[e]] - x).squaredNorm();
            if (d < best_d || (d == best_d && static_cast<int>(items_[e]) < best)) {
              best_d = d;
              best = static_cast<int>(items_[e]);
            }
          }
        }
    if (best >= 0 && std::sqrt(best_d) <= r * cell_ - slack) break;
  }
  return best;
}

}  // namespace shellfrac::brittle
