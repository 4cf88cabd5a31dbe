// Meshes as users bring them: closed but non-manifold or badly oriented meshes are refused at
// load with exact counts, the load check agrees with what the exact cutter can build, and repair
// (brittle/mesh_repair.hpp) makes the flipped and inside-out cubes into solids the exact cutter cuts.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "brittle/errors.hpp"
#include "brittle/fragments.hpp"
#include "brittle/mesh_repair.hpp"
#include "brittle/primitives.hpp"
#include "brittle/tri_mesh.hpp"
#include "crack_fixtures.hpp"

namespace shellfrac::brittle {
namespace {

// An axis-aligned cube [lo, lo + size]^3: 8 shared vertices, 12 outward triangles.
TriMesh cube(const Vec3& lo, double size) {
  TriMesh m;
  m.name = "cube";
  for (int k = 0; k < 8; ++k) m.positions.push_back(lo + size * Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  // Quads counter-clockwise seen from outside, each split along its first diagonal.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

// A tetrahedron with outward triangles (a, b, c, d positively oriented).
TriMesh tetrahedron(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  TriMesh m;
  m.positions = {a, b, c, d};
  m.triangles = {Tri(0, 2, 1), Tri(0, 1, 3), Tri(1, 2, 3), Tri(0, 3, 2)};
  return m;
}

TriMesh joined(const TriMesh& a, const TriMesh& b) {
  TriMesh m = a;
  m.append(b);
  m.name = "joined";
  return m;
}

std::string refusal(const TriMesh& m, const std::string& source) {
  try {
    require_closed_solid(m, source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_counts(const MeshReport& r, size_t boundary, size_t nm_edges, size_t nm_vertices, size_t inconsistent) {
  EXPECT_EQ(r.boundary_edges, boundary);
  EXPECT_EQ(r.non_manifold_edges, nm_edges);
  EXPECT_EQ(r.non_manifold_vertices, nm_vertices);
  EXPECT_EQ(r.inconsistent_edges, inconsistent);
}

TEST(MeshCheck, TheTestCubeIsAClosedSolid) {
  const TriMesh c = cube(Vec3::Zero(), 1.0);
  const MeshReport r = inspect_mesh(c);
  expect_counts(r, 0, 0, 0, 0);
  EXPECT_TRUE(r.closed_manifold());
  EXPECT_DOUBLE_EQ(r.volume, 1.0);
  EXPECT_EQ(refusal(c, "cube.obj"), "");
  EXPECT_TRUE(exact_cutter_accepts(c));
}

TEST(MeshCheck, TwoSolidsSharingAnEdgeHaveOneNonManifoldEdge) {
  // Tetrahedra on either side of the z axis from (0,0,0) to (0,0,1); their four faces at it meet there.
  const Vec3 p(0, 0, 0), q(0, 0, 1);
  const TriMesh tets = joined(tetrahedron(p, Vec3(1, 0, 0), Vec3(0, 1, 0), q), tetrahedron(p, Vec3(-1, 0, 0), Vec3(0, -1, 0), q));
  ASSERT_NEAR(inspect_mesh(tetrahedron(p, Vec3(1, 0, 0), Vec3(0, 1, 0), q)).volume, 1.0 / 6.0, 1e-15);
  const MeshReport r = inspect_mesh(tets);
  // The edge's ends are joined through the edge itself: counted as one edge, not also as two vertices.
  expect_counts(r, 0, 1, 0, 0);
  EXPECT_FALSE(exact_cutter_accepts(tets));
  const std::string why = refusal(tets, "tets.obj");
  EXPECT_NE(why.find("tets.obj"), std::string::npos) << why;
  EXPECT_NE(why.find("1 non-manifold edge (shared"), std::string::npos) << why;
  EXPECT_EQ(why.find("vert"), std::string::npos) << why;

  // The same with cubes [0,1]^3 and [1,2] x [1,2] x [0,1], which share the edge x = y = 1.
  const TriMesh cubes = joined(cube(Vec3::Zero(), 1.0), cube(Vec3(1, 1, 0), 1.0));
  expect_counts(inspect_mesh(cubes), 0, 1, 0, 0);
  EXPECT_FALSE(exact_cutter_accepts(cubes));
}

TEST(MeshCheck, TwoCubesTouchingAtAVertexHaveOneNonManifoldVertex) {
  const TriMesh cubes = joined(cube(Vec3::Zero(), 1.0), cube(Vec3(1, 1, 1), 1.0));
  const MeshReport r = inspect_mesh(cubes);
  expect_counts(r, 0, 0, 1, 0);
  EXPECT_TRUE(r.closed());  // closed alone once let this pass, and the cutter failed
  EXPECT_FALSE(r.closed_manifold());
  EXPECT_DOUBLE_EQ(r.volume, 2.0);
  EXPECT_FALSE(exact_cutter_accepts(cubes));
  const std::string why = refusal(cubes, "touching.obj");
  EXPECT_NE(why.find("touching.obj"), std::string::npos) << why;
  EXPECT_NE(why.find("1 non-manifold vertex (where"), std::string::npos) << why;

  // A third cube, [1,2] x [1,2] x [-1,0], touches the first at (1,1,0): two non-manifold vertices.
  const TriMesh three = joined(cubes, cube(Vec3(1, 1, -1), 1.0));
  expect_counts(inspect_mesh(three), 0, 0, 2, 0);
}

TEST(MeshCheck, AFlippedTriangleGivesItsThreeEdgesInconsistentOrientation) {
  TriMesh flipped = cube(Vec3::Zero(), 1.0);
  std::swap(flipped.triangles[5][1], flipped.triangles[5][2]);
  expect_counts(inspect_mesh(flipped), 0, 0, 0, 3);
  EXPECT_FALSE(exact_cutter_accepts(flipped));
  const std::string why = refusal(flipped, "flipped.obj");
  EXPECT_NE(why.find("flipped.obj"), std::string::npos) << why;
  EXPECT_NE(why.find("3 edges with inconsistent orientation"), std::string::npos) << why;

  // A whole flipped quad: its four sides are inconsistent, its diagonal is not.
  TriMesh quad = cube(Vec3::Zero(), 1.0);
  for (int k : {4, 5}) std::swap(quad.triangles[k][1], quad.triangles[k][2]);
  expect_counts(inspect_mesh(quad), 0, 0, 0, 4);
  EXPECT_FALSE(exact_cutter_accepts(quad));
}

TEST(MeshCheck, EveryCountIsNamedAtOnce) {
  // The edge-sharing tetrahedra, the vertex-touching cube and a flipped triangle on that cube.
  const Vec3 p(0, 0, 0), q(0, 0, 1);
  TriMesh m = joined(tetrahedron(p, Vec3(1, 0, 0), Vec3(0, 1, 0), q), tetrahedron(p, Vec3(-1, 0, 0), Vec3(0, -1, 0), q));
  TriMesh touching = cube(Vec3(1, 0, 0), 1.0);  // its corner (1,0,0) is a corner of the first tetrahedron
  std::swap(touching.triangles[0][1], touching.triangles[0][2]);
  m = joined(m, touching);
  expect_counts(inspect_mesh(m), 0, 1, 1, 3);
  const std::string why = refusal(m, "all.obj");
  EXPECT_NE(why.find("1 non-manifold edge (shared by more than two triangles), 1 non-manifold vertex (where parts touch at a "
                     "point), 3 edges with inconsistent orientation"),
            std::string::npos)
      << why;
}

TEST(MeshCheck, AnInsideOutCubeIsRefusedAsInward) {
  TriMesh inward = cube(Vec3::Zero(), 1.0);
  for (Tri& t : inward.triangles) std::swap(t[1], t[2]);
  const MeshReport r = inspect_mesh(inward);
  expect_counts(r, 0, 0, 0, 0);
  EXPECT_DOUBLE_EQ(r.volume, -1.0);
  const std::string why = refusal(inward, "inward.obj");
  EXPECT_NE(why.find("inward.obj"), std::string::npos) << why;
  EXPECT_NE(why.find("inside out (negative volume -1;"), std::string::npos) << why;
}

TEST(MeshCheck, UnweldedCoincidentVerticesAreWeldedAsTheCutterWeldsThem) {
  // box_mesh splits its vertices at every face (for normals and UVs): 6 x 4 corners for 8 positions.
  const TriMesh split = box_mesh(Vec3::Zero(), Vec3::Constant(0.5), 1);
  ASSERT_GT(split.positions.size(), 8u);
  EXPECT_TRUE(inspect_mesh(split).closed_manifold());
  EXPECT_TRUE(exact_cutter_accepts(split));
  // Unwelded, the two vertex-touching cubes meet in two distinct vertex ids at one point: both checks
  // still see one vertex there.
  TriMesh a = cube(Vec3::Zero(), 1.0), b = cube(Vec3(1, 1, 1), 1.0);
  const TriMesh touching = joined(a, b);  // append keeps b's own copy of (1,1,1)
  ASSERT_EQ(touching.positions.size(), 16u);
  EXPECT_EQ(inspect_mesh(touching).non_manifold_vertices, 1u);
  EXPECT_FALSE(exact_cutter_accepts(touching));
  // A triangle whose corners weld together is skipped by both (the cube stays a closed solid).
  TriMesh sliver = cube(Vec3::Zero(), 1.0);
  sliver.positions.push_back(sliver.positions[0]);
  sliver.triangles.emplace_back(0, 8, 1);
  EXPECT_TRUE(inspect_mesh(sliver).closed_manifold());
  EXPECT_EQ(inspect_mesh(sliver).degenerate_triangles, 1u);
  EXPECT_TRUE(exact_cutter_accepts(sliver));
}

TEST(MeshCheck, WhatTheCheckAcceptsTheCutterBuildsInAnyTriangleOrder) {
  std::mt19937 rng(29);
  const std::vector<TriMesh> solids = {cube(Vec3::Zero(), 1.0), box_mesh(Vec3::Zero(), Vec3(1, 2, 3), 3),
                                       sphere_mesh(Vec3::Zero(), 0.3, 24, 12), torus_mesh(Vec3::Zero(), 0.4, 0.1, 24, 12),
                                       cylinder_mesh(Vec3::Zero(), 0.2, 0.5, 7)};
  size_t trials = 0;
  for (TriMesh m : solids) {
    ASSERT_TRUE(inspect_mesh(m).closed_manifold());
    for (int shuffle = 0; shuffle < 20; ++shuffle) {
      std::shuffle(m.triangles.begin(), m.triangles.end(), rng);
      EXPECT_TRUE(exact_cutter_accepts(m)) << shuffle;
      ++trials;
    }
  }
  EXPECT_EQ(trials, 100u);
}

// The repaired cubes: closed manifolds of the cube's volume, cut by the exact cutter into two halves.
void expect_cuttable_cube(const TriMesh& repaired, double half) {
  const MeshReport r = inspect_mesh(repaired);
  EXPECT_TRUE(r.closed_manifold());
  expect_counts(r, 0, 0, 0, 0);
  const double volume = 8 * half * half * half;
  EXPECT_NEAR(r.volume, mass_properties(cube(Vec3::Constant(-half), 2 * half), 1.0).volume, 1e-12);
  EXPECT_NEAR(r.volume, volume, 1e-12);
  EXPECT_EQ(repaired.positions.size(), 8u);
  EXPECT_EQ(repaired.triangles.size(), 12u);
  EXPECT_TRUE(exact_cutter_accepts(repaired));
  // A slab of damage at z = 0 in the cube's particles: the crack splits it into two halves.
  const testing::DamagedBox box(half, half / 10, [&](const Vec3& p) { return std::abs(p.z()) < half / 10; });
  CrackExtractionOptions co;
  co.grid.spacing = half / 5;
  const CrackExtraction crack = extract_crack(box.x, box.c_his, co);
  const Regions regions = find_regions(crack.diagram, crack.crack_face);
  FragmentOptions fo;
  fo.cutter = Cutter::Exact;
  const FragmentSet set = cut_fragments(repaired, crack.diagram, regions, fo, "repaired.obj");
  ASSERT_EQ(set.fragments.size(), 2u);
  EXPECT_NEAR(set.input_volume, volume, 1e-12);
  EXPECT_LT(std::abs(set.volume_change()), 1e-9);
  for (const Fragment& f : set.fragments) {
    EXPECT_TRUE(inspect_mesh(f.mesh).closed_manifold()) << f.mesh.name;
    EXPECT_NEAR(f.properties.volume, 0.5 * volume, 0.05 * volume) << f.mesh.name;
  }
}

TEST(MeshCheck, RepairTurnsTheFlippedTriangleBack) {
  const double half = 0.05;
  TriMesh flipped = cube(Vec3::Constant(-half), 2 * half);
  std::swap(flipped.triangles[5][1], flipped.triangles[5][2]);
  MeshRepair changes;
  const TriMesh repaired = repair_closed_solid(flipped, "flipped.obj", changes);
  EXPECT_EQ(changes.reversed_triangles, 1u);
  EXPECT_EQ(changes.removed_triangles, 0u);
  EXPECT_EQ(changes.removed_vertices, 0u);
  EXPECT_EQ(changes.split_vertices, 0u);
  EXPECT_EQ(changes.stitched_edges, 0u);
  EXPECT_EQ(changes.describe(), "1 triangle reversed");
  expect_cuttable_cube(repaired, half);
}

TEST(MeshCheck, RepairTurnsAnInsideOutCubeOutward) {
  const double half = 0.05;
  TriMesh inward = cube(Vec3::Constant(-half), 2 * half);
  for (Tri& t : inward.triangles) std::swap(t[1], t[2]);
  MeshRepair changes;
  const TriMesh repaired = repair_closed_solid(inward, "inward.obj", changes);
  EXPECT_EQ(changes.reversed_triangles, 12u);
  EXPECT_EQ(changes.describe(), "12 triangles reversed");
  expect_cuttable_cube(repaired, half);
}

TEST(MeshCheck, RepairWeldsSplitVerticesAndDropsDuplicates) {
  // box_mesh's 24 split corners of 8 positions, one triangle given twice, one flipped.
  TriMesh m = box_mesh(Vec3::Zero(), Vec3::Constant(0.05), 1);
  const size_t corners = m.positions.size();
  m.triangles.push_back(m.triangles[0]);
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  MeshRepair changes;
  const TriMesh repaired = repair_closed_solid(m, "box.obj", changes);
  EXPECT_EQ(changes.removed_vertices, corners - 8);
  EXPECT_EQ(changes.removed_triangles, 1u);
  EXPECT_EQ(changes.reversed_triangles, 1u);
  EXPECT_TRUE(repaired.normals.empty());
  EXPECT_TRUE(repaired.uvs.empty());
  expect_counts(inspect_mesh(repaired), 0, 0, 0, 0);
  EXPECT_NEAR(inspect_mesh(repaired).volume, 0.001, 1e-12);
}

TEST(MeshCheck, RepairCannotSeparateSolidsTouchingAtAPoint) {
  // Orienting the soup splits the shared vertex, but the split copies are coincident: the exact cutter
  // would weld them back, so the result is refused with the count after repair.
  const TriMesh cubes = joined(cube(Vec3::Zero(), 1.0), cube(Vec3(1, 1, 1), 1.0));
  MeshRepair changes;
  try {
    repair_closed_solid(cubes, "touching.obj", changes);
    FAIL() << "two cubes touching at a vertex were repaired";
  } catch (const InputError& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("touching.obj (after repair: "), std::string::npos) << why;
    EXPECT_NE(why.find("1 non-manifold vertex"), std::string::npos) << why;
  }
  EXPECT_EQ(changes.split_vertices, 1u);
  // A hole cannot be repaired (no filling): refused with its boundary-edge count.
  TriMesh open = cube(Vec3::Zero(), 1.0);
  open.triangles.pop_back();
  try {
    repair_closed_solid(open, "open.obj", changes);
    FAIL() << "an open cube was repaired";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("3 boundary edges (holes)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shellfrac::brittle
