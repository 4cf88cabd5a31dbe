// Collision meshes: meshoptimizer's decimation within the face budget, closed and close in volume; the
// hull ratio that picks convex shapes.
#include <gtest/gtest.h>

#include "brittle/primitives.hpp"
#include "rigid/collision_mesh.hpp"

namespace shellfrac::rigid {
namespace {

TEST(CollisionMesh, DecimatedSphereStaysClosedWithinTheBudget) {
  const brittle::TriMesh sphere = brittle::sphere_mesh(brittle::Vec3::Zero(), 0.1, 96, 48);
  ASSERT_GT(sphere.num_triangles(), 8000u);
  const DecimatedMesh d = decimate(sphere, 1000);
  EXPECT_LE(d.mesh.num_triangles(), 1000u);
  EXPECT_GE(d.mesh.num_triangles(), 500u);  // it stops near the budget, not far below
  const brittle::MeshReport r = brittle::inspect_mesh(d.mesh);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  // A sphere of 1000 triangles holds about 0.4 % less volume than the true sphere; 2 % bounds it.
  const double exact = 4.0 / 3.0 * 3.14159265358979 * 1e-3;
  EXPECT_NEAR(r.volume, exact, 0.02 * exact);
}

TEST(CollisionMesh, WithinTheBudgetOnlyWelds) {
  const brittle::TriMesh box = brittle::box_mesh(brittle::Vec3::Zero(), brittle::Vec3(1, 1, 1), 1);
  const DecimatedMesh d = decimate(box, 1000);
  EXPECT_EQ(d.mesh.num_triangles(), 12u);
  EXPECT_EQ(d.mesh.num_vertices(), 8u);  // the box's split vertices welded
  EXPECT_NEAR(brittle::inspect_mesh(d.mesh).volume, 8.0, 1e-12);
}

TEST(CollisionMesh, HullRatioTellsConvexFromConcave) {
  const brittle::TriMesh box = brittle::box_mesh(brittle::Vec3::Zero(), brittle::Vec3(0.3, 0.2, 0.1), 2);
  EXPECT_NEAR(hull_volume_ratio(box), 1.0, 1e-12);
  // Torus R = 0.2, r = 0.05: its hull is a cylinder of radius R and height 2r plus the outer half of the
  // tube (Pappus: pi^2 r^2 (R + 4r / 3pi)), over the torus's 2 pi^2 R r^2: 1.8263. 3 % for the facets.
  const brittle::TriMesh torus = brittle::torus_mesh(brittle::Vec3::Zero(), 0.2, 0.05, 96, 48);
  const double pi = 3.14159265358979, R = 0.2, r = 0.05;
  const double hull = pi * R * R * 2 * r + pi * pi * r * r * (R + 4 * r / (3 * pi));
  EXPECT_NEAR(hull_volume_ratio(torus), hull / (2 * pi * pi * R * r * r), 0.03 * 1.8263);
}

}  // namespace
}  // namespace shellfrac::rigid
