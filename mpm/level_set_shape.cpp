#include "mpm/level_set_shape.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <mutex>
#include <stdexcept>

namespace shellfrac::mpm {

struct LevelSetShape::Grid {
  openvdb::FloatGrid::Ptr grid;
};

LevelSetShape::LevelSetShape(const std::vector<Vec3>& vertices, const std::vector<Eigen::Vector3i>& triangles,
                             double voxel, double band_voxels)
    : grid_(std::make_unique<Grid>()), voxel_(voxel) {
  if (vertices.empty() || triangles.empty()) throw std::invalid_argument("mesh has no triangles");
  if (!(voxel > 0)) throw std::invalid_argument("level set voxel size must be > 0");
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  std::vector<openvdb::Vec3s> points;
  points.reserve(vertices.size());
  lo_ = hi_ = vertices.front();
  for (const Vec3& v : vertices) {
    points.emplace_back(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
    lo_ = lo_.cwiseMin(v);
    hi_ = hi_.cwiseMax(v);
  }
  std::vector<openvdb::Vec3I> tris;
  tris.reserve(triangles.size());
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || static_cast<size_t>(t[k]) >= vertices.size())
        throw std::invalid_argument("mesh triangle refers to a vertex that does not exist");
    tris.emplace_back(static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]), static_cast<unsigned>(t[2]));
  }
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  grid_->grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, tris, static_cast<float>(band_voxels));
}

LevelSetShape::~LevelSetShape() = default;

double LevelSetShape::signed_distance(const Vec3& x) const {
  const openvdb::tools::GridSampler<openvdb::FloatTree, openvdb::tools::BoxSampler> sampler(
      grid_->grid->tree(), grid_->grid->transform());
  return sampler.wsSample(openvdb::Vec3R(x.x(), x.y(), x.z()));
}

Vec3 LevelSetShape::normal(const Vec3& x) const {
  const double h = 0.5 * voxel_;
  Vec3 g;
  for (int d = 0; d < 3; ++d) {
    Vec3 a = x, b = x;
    a[d] += h;
    b[d] -= h;
    g[d] = signed_distance(a) - signed_distance(b);
  }
  const double n = g.norm();
  return n > 0 ? Vec3(g / n) : Vec3::UnitZ();
}

size_t LevelSetShape::active_voxels() const { return grid_->grid->activeVoxelCount(); }

}  // namespace shellfrac::mpm
