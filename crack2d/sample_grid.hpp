#pragma once
// Bucket grid over the sample (quadrature) points of one patch in parameter space: neighbours within a
// radius and the nearest sample, both without O(n^2) scans. Used to classify boundary seeds and to ask
// "is this location inside the fully damaged region?" (nearest sample point damaged).
#include "crack2d/geometry.hpp"

#include <vector>

namespace shellfrac::crack2d {

class SampleGrid {
 public:
  // cell: bucket size, about the largest query radius used (queries of any radius stay correct).
  SampleGrid(const std::vector<Point>& points, double cell);

  // Calls visit(i) for every sample i with |points[i] - p| <= radius, in increasing bucket order.
  template <class Visit>
  void for_each_within(const Point& p, double radius, Visit&& visit) const {
    if (points_.empty()) return;
    const int c0 = column(p.x() - radius), c1 = column(p.x() + radius);
    const int r0 = row(p.y() - radius), r1 = row(p.y() + radius);
    const double r2 = radius * radius;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        const size_t cell = static_cast<size_t>(r) * nx_ + c;
        for (int k = start_[cell]; k < start_[cell + 1]; ++k) {
          const int i = order_[k];
          if ((points_[i] - p).squaredNorm() <= r2) visit(i);
        }
      }
  }

  // Index of the sample nearest to p (lowest index on ties), or -1 when none lies within max_radius.
  int nearest(const Point& p, double max_radius) const;
  size_t size() const { return points_.size(); }

 private:
  int column(double x) const;
  int row(double y) const;

  const std::vector<Point>& points_;
  Point origin_ = Point::Zero();
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<int> start_;  // CSR bucket offsets, size nx_*ny_ + 1
  std::vector<int> order_;  // sample indices sorted by bucket
};

}  // namespace shellfrac::crack2d
