#include "mpm/level_set_shape.hpp"

#include <gtest/gtest.h>

#include "mpm/solid_particles.hpp"

namespace shellfrac::mpm {
namespace {

// An axis-aligned box as a closed, outward-oriented triangle mesh.
void box_mesh(const Vec3& lo, const Vec3& hi, std::vector<Vec3>& v, std::vector<Eigen::Vector3i>& t) {
  for (int k = 0; k < 8; ++k) v.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    t.emplace_back(q[0], q[1], q[2]);
    t.emplace_back(q[0], q[2], q[3]);
  }
}

TEST(LevelSetShape, MatchesTheBoxDistanceNearItsSurface) {
  std::vector<Vec3> v;
  std::vector<Eigen::Vector3i> t;
  box_mesh(Vec3(-0.2, -0.1, -0.3), Vec3(0.2, 0.1, 0.3), v, t);
  const double voxel = 0.01;
  const LevelSetShape ls(v, t, voxel, 3.0);
  const Box box(Vec3::Zero(), Vec3(0.2, 0.1, 0.3));
  // Within the narrow band the field is the signed distance to within a voxel.
  for (const Vec3& p : {Vec3(0.21, 0, 0), Vec3(0.19, 0.02, 0.1), Vec3(0, 0.115, 0), Vec3(0.05, -0.09, 0.29),
                        Vec3(-0.1, 0.0, -0.31)})
    EXPECT_NEAR(ls.signed_distance(p), box.signed_distance(p), voxel) << p.transpose();
  EXPECT_LT(ls.signed_distance(Vec3::Zero()), 0.0);      // deep inside: negative
  EXPECT_GT(ls.signed_distance(Vec3(1, 1, 1)), 0.0);     // far outside: positive
  EXPECT_LE((ls.normal(Vec3(0.205, 0.0, 0.0)) - Vec3(1, 0, 0)).norm(), 0.05);
  EXPECT_GT(ls.active_voxels(), 0u);
  // Particles sampled inside the mesh fill its volume at the requested density.
  const auto pts = sample_jittered(ls, ls.lower(), ls.upper(), 0.02, 5);
  const double expected = 0.4 * 0.2 * 0.6 / (0.02 * 0.02 * 0.02);
  EXPECT_NEAR(static_cast<double>(pts.size()), expected, 0.05 * expected);
}

TEST(LevelSetShape, RejectsEmptyMeshesAndBadIndices) {
  EXPECT_THROW(LevelSetShape({}, {}, 0.01), std::invalid_argument);
  EXPECT_THROW(LevelSetShape({Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()}, {Eigen::Vector3i(0, 1, 5)}, 0.01),
               std::invalid_argument);
}

}  // namespace
}  // namespace shellfrac::mpm
