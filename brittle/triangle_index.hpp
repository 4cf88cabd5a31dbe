#pragma once
#include <cstdint>
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// Closest point on triangle abc to x, with its barycentric coordinates (u, v, w), x_c = u a + v b + w c.
Vec3 closest_point_on_triangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* barycentric = nullptr);

// A uniform bucket grid over triangles for closest-point queries within a bounded distance (the crack
// surface for the two velocity fields, the input surface for attribute transfer): a query searches rings
// of buckets outwards from its own and stops as soon as no unsearched bucket can hold a closer point;
// a per-bucket Chebyshev distance to the nearest occupied bucket answers "nothing within reach" at once.
// It never loops over every face.
class TriangleIndex {
 public:
  TriangleIndex() = default;
  // bucket_size: about the triangles' size; max_reach: the largest max_distance queries will use.
  TriangleIndex(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, double bucket_size,
                double max_reach = 0);
  struct Hit {
    bool found = false;
    double distance = 0;
    Vec3 point = Vec3::Zero();
    int triangle = -1;
    Vec3 barycentric = Vec3::Zero();
  };
  // Closest point of any triangle within max_distance of x (found = false if none).
  Hit closest(const Vec3& x, double max_distance) const;
  bool empty() const { return triangles_.empty(); }
  const Vec3& triangle_normal(int t) const { return normals_[static_cast<size_t>(t)]; }

 private:
  std::vector<Vec3> positions_;
  std::vector<Tri> triangles_;
  std::vector<Vec3> normals_;  // unit (zero for degenerate triangles)
  std::vector<Eigen::Vector4d> spheres_;  // bounding sphere (centre, radius) of each triangle: cheap rejection
  double cell_ = 1, inv_cell_ = 1;
  Vec3 lo_ = Vec3::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<uint32_t> offsets_, items_;  // CSR of triangles per bucket
  std::vector<uint8_t> rings_;             // Chebyshev distance (in buckets) to an occupied bucket, capped
};

}  // namespace shellfrac::brittle
