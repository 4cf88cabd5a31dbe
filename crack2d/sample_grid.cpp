#include "crack2d/sample_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::crack2d {

namespace {
constexpr double kMaxBuckets = 4.0e6;  // caps memory when the caller's cell is tiny relative to the extent
}

SampleGrid::SampleGrid(const std::vector<Point>& points, double cell) : points_(points) {
  if (points_.empty()) {
    start_.assign(2, 0);
    return;
  }
  Point lo = points_[0], hi = points_[0];
  for (const Point& p : points_) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Point extent = (hi - lo).cwiseMax(Point::Constant(1e-300));
  cell_ = cell > 0.0 ? cell : std::max(extent.x(), extent.y());
  while ((extent.x() / cell_ + 1.0) * (extent.y() / cell_ + 1.0) > kMaxBuckets) cell_ *= 2.0;
  origin_ = lo;
  nx_ = static_cast<int>(extent.x() / cell_) + 1;
  ny_ = static_cast<int>(extent.y() / cell_) + 1;
  const size_t buckets = static_cast<size_t>(nx_) * ny_;
  start_.assign(buckets + 1, 0);
  std::vector<int> bucket_of(points_.size());
  for (size_t i = 0; i < points_.size(); ++i) {
    bucket_of[i] = row(points_[i].y()) * nx_ + column(points_[i].x());
    ++start_[bucket_of[i] + 1];
  }
  for (size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  order_.resize(points_.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) order_[fill[bucket_of[i]]++] = static_cast<int>(i);
}

int SampleGrid::column(double x) const {
  const double c = std::floor((x - origin_.x()) / cell_);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(nx_ - 1)));
}

int SampleGrid::row(double y) const {
  const double r = std::floor((y - origin_.y()) / cell_);
  return static_cast<int>(std::clamp(r, 0.0, static_cast<double>(ny_ - 1)));
}

int SampleGrid::nearest(const Point& p, double max_radius) const {
  if (points_.empty()) return -1;
  int best = -1;
  double best_d2 = max_radius * max_radius;
  const int pc = column(p.x()), pr = row(p.y());
  const int max_ring = std::max(nx_, ny_);
  for (int ring = 0; ring <= max_ring; ++ring) {
    // Any sample first met in ring k is more than (k-1) cells away (clamping only shrinks index gaps).
    const double bound = (ring - 1) * cell_;
    if (ring >= 1 && bound * bound > best_d2) break;
    for (int r = std::max(pr - ring, 0); r <= std::min(pr + ring, ny_ - 1); ++r) {
      const bool full_row = (r == pr - ring || r == pr + ring);
      for (int c = std::max(pc - ring, 0); c <= std::min(pc + ring, nx_ - 1); ++c) {
        if (!full_row && c != pc - ring && c != pc + ring) continue;
        const size_t cell = static_cast<size_t>(r) * nx_ + c;
        for (int k = start_[cell]; k < start_[cell + 1]; ++k) {
          const int i = order_[k];
          const double d2 = (points_[i] - p).squaredNorm();
          if (d2 < best_d2 || (d2 == best_d2 && (best < 0 || i < best))) {
            best_d2 = d2;
            best = i;
          }
        }
      }
    }
  }
  return best;
}

}  // namespace shellfrac::crack2d
