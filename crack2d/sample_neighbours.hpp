#pragma once
// Fixed-radius neighbour lists of the sample points (compressed rows), built once and reused: the
// quadrature points of a patch never move in the parameter plane, so every extraction of that patch asks
// the same neighbour queries. Row i lists the samples within the radius of sample i (i itself included)
// in the order SampleGrid::for_each_within visits them.
#include "crack2d/sample_grid.hpp"

#include <vector>

namespace shellfrac::crack2d {

class SampleNeighbours {
 public:
  SampleNeighbours() = default;
  SampleNeighbours(const std::vector<Point>& points, const SampleGrid& grid, double radius) : radius_(radius) {
    start_.assign(1, 0);
    start_.reserve(points.size() + 1);
    for (const Point& p : points) {
      grid.for_each_within(p, radius, [&](int j) { list_.push_back(j); });
      start_.push_back(static_cast<int>(list_.size()));
    }
  }
  template <class Visit>
  void for_each(size_t i, Visit&& visit) const {
    for (int k = start_[i]; k < start_[i + 1]; ++k) visit(list_[k]);
  }
  double radius() const { return radius_; }

 private:
  double radius_ = 0.0;
  std::vector<int> start_{0};
  std::vector<int> list_;
};

}  // namespace shellfrac::crack2d
