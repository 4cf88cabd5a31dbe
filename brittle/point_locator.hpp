#pragma once
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// A fixed point set binned into cubic buckets of edge `cell` over its bounding box: the points of bucket
// k are items[offsets[k] .. offsets[k + 1]).
struct PointBuckets {
  PointBuckets() = default;
  PointBuckets(const std::vector<Vec3>& points, double cell);
  // The bucket holding x (clamped into the grid) and its flat index.
  Eigen::Vector3i bucket(const Vec3& x) const;
  size_t index(const Eigen::Vector3i& b) const { return static_cast<size_t>(b.x() + dims.x() * (b.y() + dims.y() * b.z())); }
  bool inside(const Eigen::Vector3i& b) const { return (b.array() >= 0).all() && (b.array() < dims.array()).all(); }

  double cell = 1;
  Vec3 lo = Vec3::Zero();
  Eigen::Vector3i dims = Eigen::Vector3i::Ones();
  std::vector<uint32_t> offsets, items;
};

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
  PointBuckets buckets_;
};

}  // namespace shellfrac::brittle
