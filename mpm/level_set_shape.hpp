#pragma once
#include <memory>
#include <vector>

#include "mpm/colliders.hpp"

namespace shellfrac::mpm {

// A closed triangle mesh as a narrow-band signed distance field (OpenVDB level set), usable as a
// collider shape and as the region Type-I particles are sampled in. Within the band the value is the
// trilinearly interpolated signed distance; beyond it, +band outside and -band inside.
class LevelSetShape : public Shape {
 public:
  // vertices in world units; triangles index them; voxel = grid spacing of the field; band in voxels.
  LevelSetShape(const std::vector<Vec3>& vertices, const std::vector<Eigen::Vector3i>& triangles, double voxel,
                double band_voxels = 3.0);
  ~LevelSetShape() override;

  double signed_distance(const Vec3& x) const override;
  Vec3 normal(const Vec3& x) const override;  // normalised central-difference gradient of the field
  const Vec3& lower() const { return lo_; }   // bounding box of the mesh
  const Vec3& upper() const { return hi_; }
  size_t active_voxels() const;

 private:
  struct Grid;
  std::unique_ptr<Grid> grid_;
  double voxel_;
  Vec3 lo_, hi_;
};

}  // namespace shellfrac::mpm
