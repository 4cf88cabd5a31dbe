#pragma once
// "Inside the fully damaged region" for one extraction (thesis sec. 4.4.2): a location is inside when
// its nearest sample point is damaged, i.e. the damaged region is the union of the Voronoi cells of the
// damaged samples. Farther than `max_radius` from every sample counts as outside.
#include "crack2d/sample_neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace shellfrac::crack2d {

class DamageField {
 public:
  // All references must outlive the field. neighbours: the sample adjacency (boundary of the damaged
  // region, intact pieces); probe_step: spacing of the probes of damaged_along().
  DamageField(const std::vector<Point>& points, const std::vector<unsigned char>& damaged, const SampleGrid& grid,
              const SampleNeighbours& neighbours, double max_radius, double probe_step)
      : points_(points), damaged_(damaged), grid_(grid), neighbours_(neighbours), max_radius_(max_radius),
        probe_step_(probe_step) {}

  const SampleGrid& grid() const { return grid_; }
  const SampleNeighbours& neighbours() const { return neighbours_; }
  const std::vector<Point>& points() const { return points_; }
  const std::vector<unsigned char>& flags() const { return damaged_; }

  bool damaged_at(const Point& p) const {
    const int i = grid_.nearest(p, max_radius_);
    return i >= 0 && damaged_[i] != 0;
  }
  // Probes every probe_step along the closed segment ab, both ends included.
  bool damaged_along(const Point& a, const Point& b) const {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / probe_step_)));
    for (int k = 0; k <= steps; ++k)
      if (!damaged_at(a + (b - a) * (static_cast<double>(k) / steps))) return false;
    return true;
  }

 private:
  const std::vector<Point>& points_;
  const std::vector<unsigned char>& damaged_;
  const SampleGrid& grid_;
  const SampleNeighbours& neighbours_;
  double max_radius_;
  double probe_step_;
};

}  // namespace shellfrac::crack2d
