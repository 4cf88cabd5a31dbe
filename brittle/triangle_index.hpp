#pragma once
#include <cstdint>
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// Closest point on triangle abc to x, with its barycentric coordinates (u, v, w), x_c = u a + v b + w c.
Vec3 closest_point_on_triangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* barycentric = nullptr);

// A uniform bucket grid over triangles for closest-point queries within a bounded distance (the crack
// surface for the two velocity fields, the input surface for attribute transfer): a query visits only the
// buckets its search ball touches, never every face.
class TriangleIndex {
 public:
  TriangleIndex() = default;
  TriangleIndex(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, double bucket_size);
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
  uint64_t key(long i, long j, long k) const;
  std::vector<Vec3> positions_;
  std::vector<Tri> triangles_;
  std::vector<Vec3> normals_;  // unit (zero for degenerate triangles)
  double cell_ = 1, inv_cell_ = 1;
  std::vector<uint64_t> keys_;        // sorted bucket keys
  std::vector<uint32_t> offsets_;     // CSR into items_
  std::vector<uint32_t> items_;
};

}  // namespace shellfrac::brittle
