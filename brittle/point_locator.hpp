#pragma once
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// Nearest-point queries over a fixed point set (Voronoi sites, particles) through a uniform bucket
// grid: a query searches rings of buckets until no unsearched bucket can hold a closer point.
class PointLocator {
 public:
  PointLocator() = default;
  explicit PointLocator(const std::vector<Vec3>& points);
  // Index of the point nearest to x (ties to the lower index), -1 for an empty set.
  int nearest(const Vec3& x) const;

 private:
  const std::vector<Vec3>* points_ = nullptr;
  double cell_ = 1;
  Vec3 lo_ = Vec3::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  std::vector<uint32_t> offsets_, items_;  // CSR of points per bucket
};

}  // namespace shellfrac::brittle
