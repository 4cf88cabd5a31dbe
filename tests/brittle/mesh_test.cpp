#include <gtest/gtest.h>

#include <cmath>

#include "brittle/errors.hpp"
#include "brittle/primitives.hpp"
#include "brittle/tri_mesh.hpp"
#include "brittle/triangle_index.hpp"

#include <random>

namespace shellfrac::brittle {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(TriMesh, PrimitivesAreClosedWithTheirAnalyticVolume) {
  struct Case {
    TriMesh mesh;
    double exact, tolerance;  // polygonal approximations of curved solids lose a known fraction
  };
  const int n = 64;
  // Inscribed polygons: the cylinder's cross-section is (n/2) sin(2 pi/n) r^2 of pi r^2.
  const double polygon = 0.5 * n * std::sin(2 * kPi / n) / kPi;
  const std::vector<Case> cases = {
      {box_mesh(Vec3(1, 2, 3), Vec3(0.5, 0.25, 0.125), 3), 1.0 * 0.5 * 0.25, 1e-14},
      {cylinder_mesh(Vec3(0, 0, 0), 0.2, 0.5, n), polygon * kPi * 0.04 * 0.5, 1e-12},
      {sphere_mesh(Vec3(0, 0, 0), 0.3, n, n / 2), 4.0 / 3.0 * kPi * 0.027, 0.005},
      // Pappus with polygons: ring factor n sin(2 pi/n) / (2 pi), tube polygon area (m/2) sin(2 pi/m) r^2.
      {torus_mesh(Vec3(0, 0, 0), 0.4, 0.1, n, n / 2),
       n * std::sin(2 * kPi / n) * 0.4 * (n / 4.0) * std::sin(4 * kPi / n) * 0.01, 2e-3},
  };
  for (const Case& c : cases) {
    const MeshReport r = inspect_mesh(c.mesh);
    EXPECT_TRUE(r.closed()) << c.mesh.name;
    EXPECT_EQ(r.inconsistent_edges, 0u) << c.mesh.name;
    EXPECT_EQ(r.degenerate_triangles, 0u) << c.mesh.name;
    EXPECT_NEAR(r.volume, c.exact, c.tolerance * c.exact) << c.mesh.name;
    EXPECT_NO_THROW(require_closed_solid(c.mesh, c.mesh.name));
  }
  // Segment counts that are not powers of two round angles differently: seams must still weld.
  for (int segments : {3, 7, 48, 100}) {
    EXPECT_TRUE(inspect_mesh(cylinder_mesh(Vec3::Zero(), 0.1, 0.2, segments)).closed()) << segments;
    EXPECT_TRUE(inspect_mesh(sphere_mesh(Vec3::Zero(), 0.1, segments, segments / 2 + 2)).closed()) << segments;
    EXPECT_TRUE(inspect_mesh(torus_mesh(Vec3::Zero(), 0.3, 0.1, segments, segments / 2 + 3)).closed()) << segments;
  }
}

TEST(TriMesh, MassPropertiesOfABoxMatchTheTextbook) {
  // A 0.4 x 0.2 x 0.1 box of density 2500: I_xx = m (b^2 + c^2) / 12 etc., products of inertia 0.
  const TriMesh box = box_mesh(Vec3(0.3, -0.2, 0.7), Vec3(0.2, 0.1, 0.05), 2);
  const MassProperties mp = mass_properties(box, 2500.0);
  const double m = 2500.0 * 0.4 * 0.2 * 0.1;
  EXPECT_NEAR(mp.volume, 0.008, 1e-15);
  EXPECT_NEAR(mp.mass, m, 1e-12);
  EXPECT_LT((mp.centroid - Vec3(0.3, -0.2, 0.7)).norm(), 1e-14);
  const Vec3 expected(m * (0.04 + 0.01) / 12, m * (0.16 + 0.01) / 12, m * (0.16 + 0.04) / 12);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(mp.inertia(a, a), expected[a], 1e-12 * expected[a]);
  EXPECT_LT((mp.inertia - Mat3(expected.asDiagonal())).norm(), 1e-13);
}

TEST(TriMesh, OpenMeshIsRefusedWithItsBoundaryEdgeCount) {
  TriMesh box = box_mesh(Vec3::Zero(), Vec3::Ones(), 1);
  box.name = "scan";
  box.triangles.pop_back();  // a hole: one triangle missing leaves 3 boundary edges
  const MeshReport r = inspect_mesh(box);
  EXPECT_EQ(r.boundary_edges, 3u);
  try {
    require_closed_solid(box, "meshes/scan.obj");
    FAIL() << "an open mesh was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("meshes/scan.obj"), std::string::npos) << what;
    EXPECT_NE(what.find("3 boundary edges"), std::string::npos) << what;
  }
}

TEST(TriMesh, NanZeroVolumeAndInsideOutAreRefused) {
  TriMesh nan_mesh = box_mesh(Vec3::Zero(), Vec3::Ones(), 1);
  nan_mesh.positions[3].x() = std::nan("");
  EXPECT_THROW(require_closed_solid(nan_mesh, "nan.obj"), InputError);
  try {
    require_closed_solid(nan_mesh, "nan.obj");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);
  }
  // A flat, closed "box" (zero thickness) encloses nothing.
  TriMesh flat = box_mesh(Vec3::Zero(), Vec3(1, 1, 0), 1);
  EXPECT_THROW(require_closed_solid(flat, "flat.obj"), InputError);
  TriMesh inverted = box_mesh(Vec3::Zero(), Vec3::Ones(), 1);
  for (Tri& t : inverted.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(require_closed_solid(inverted, "inverted.obj"), InputError);
  TriMesh empty;
  EXPECT_THROW(require_closed_solid(empty, "empty.obj"), InputError);
}

TEST(TriangleIndex, ClosestPointsMatchABruteForceSearch) {
  const TriMesh mesh = torus_mesh(Vec3(0.1, 0, 0), 0.3, 0.1, 24, 12);
  const double reach = 0.15;
  const TriangleIndex index(mesh.positions, mesh.triangles, 0.03, reach);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  int found = 0;
  for (int q = 0; q < 2000; ++q) {
    const Vec3 x(u(rng), u(rng), 0.5 * u(rng));
    double best = std::numeric_limits<double>::infinity();
    for (const Tri& t : mesh.triangles)
      best = std::min(best, (closest_point_on_triangle(x, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) - x).norm());
    const TriangleIndex::Hit hit = index.closest(x, reach);
    EXPECT_EQ(hit.found, best < reach) << q;
    if (hit.found) {
      EXPECT_NEAR(hit.distance, best, 1e-12) << q;
      ++found;
    }
  }
  EXPECT_GT(found, 200);
}

}  // namespace
}  // namespace shellfrac::brittle
