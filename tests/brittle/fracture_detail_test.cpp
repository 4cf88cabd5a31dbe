// Fracture detail from the damage time (thesis sec. 3.7): the damage-time gradient against a linear field
// (Eq. 3.13, 3.14), the refinement of crack faces, Algorithm 4's lines on a plane, and chevron marks on
// the two halves of a cut block, which must still fit together.
#include "brittle/fracture_detail.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "brittle/crack_surface.hpp"
#include "brittle/errors.hpp"
#include "brittle/primitives.hpp"
#include "brittle/regions.hpp"
#include "crack_fixtures.hpp"

namespace shellfrac::brittle {
namespace {

TEST(FractureDetail, DamageTimeGradientOfALinearFieldIsExact) {
  // Broken particles on a lattice of spacing h/2 aligned with the nodes, tau linear in x: every node's
  // Eq. 3.13 mean is the field at the node (its particles lie symmetrically around it), the quadratic
  // weights reproduce linear functions, and sum_i w_i (x_i - x)(x_i - x)^T = h^2/4 I, so Eq. 3.14 returns
  // the field's gradient exactly wherever the stencil is full.
  const double h = 0.1;
  const Vec3 slope(2.0, -1.0, 0.5);
  std::vector<Vec3> rest;
  std::vector<ParticleDamage> damage;
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j)
      for (int k = -12; k <= 12; ++k) {
        const Vec3 p(0.5 * h * i, 0.5 * h * j, 0.5 * h * k);
        rest.push_back(p);
        ParticleDamage d;
        d.tau = 3.0 + slope.dot(p);
        damage.push_back(d);
      }
  ParticleDamage intact;  // tau = -1: never broken, must not count
  rest.push_back(Vec3(0.01, 0.02, 0.03));
  damage.push_back(intact);
  const DamageTimeGrid grid(rest, damage, h);
  for (const Vec3& x : {Vec3(0.013, -0.072, 0.151), Vec3(-0.2, 0.1, 0.0), Vec3(0.24, 0.19, -0.23)}) {
    ASSERT_TRUE(grid.time(x).has_value());
    EXPECT_NEAR(*grid.time(x), 3.0 + slope.dot(x), 1e-12);
    EXPECT_LT((grid.gradient(x) - slope).norm(), 1e-10 * slope.norm()) << x.transpose();
  }
  EXPECT_FALSE(grid.time(Vec3(5, 5, 5)).has_value());
  EXPECT_EQ(grid.gradient(Vec3(5, 5, 5)), Vec3::Zero());
}

TEST(FractureDetail, RefinementSplitsOnlyCrackEdgesAndKeepsTheCubeClosed) {
  TriMesh cube = box_mesh(Vec3::Zero(), Vec3::Constant(0.5), 1);
  // The top face (z = 0.5) is the crack.
  std::vector<char> crack(cube.triangles.size(), 0);
  size_t top = 0;
  for (size_t t = 0; t < cube.triangles.size(); ++t) {
    bool up = true;
    for (int k = 0; k < 3; ++k) up = up && cube.positions[static_cast<size_t>(cube.triangles[t][k])].z() == 0.5;
    crack[t] = up;
    top += up;
  }
  ASSERT_GT(top, 0u);
  const double volume = mass_properties(cube, 1.0).volume;
  refine_crack_faces(cube, crack, 0.1);
  const MeshReport report = inspect_mesh(cube);
  EXPECT_TRUE(report.closed_manifold());
  EXPECT_NEAR(mass_properties(cube, 1.0).volume, volume, 1e-13);  // round-off of the divergence sum
  double longest = 0;
  size_t crack_count = 0;
  for (size_t t = 0; t < cube.triangles.size(); ++t) {
    if (!crack[t]) continue;
    ++crack_count;
    for (int e = 0; e < 3; ++e)
      longest = std::max(longest, (cube.positions[static_cast<size_t>(cube.triangles[t][e])] -
                                   cube.positions[static_cast<size_t>(cube.triangles[t][(e + 1) % 3])]).norm());
  }
  EXPECT_LE(longest, 0.1);
  // A unit square of edges at most 0.1 needs at least 1 / (sqrt(3)/4 0.1^2) triangles.
  EXPECT_GE(static_cast<double>(crack_count), 1.0 / (std::sqrt(3.0) / 4.0 * 0.01));
}

TEST(FractureDetail, ChevronLinesRunDownTheDamageTimeGradient) {
  // A 21 x 21 plane of points 1 cm apart, broken from x = 0 towards +x: every line of two or more points
  // runs along +x on one row; a line marks its neighbouring rows as visited (radius 1.5 cm), so the lines
  // lie on every other row and go the whole 20 cm.
  std::vector<Vec3> points, normals, gradient;
  std::vector<double> time;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      points.emplace_back(0.01 * i, 0.01 * j, 0.0);
      normals.push_back(Vec3::UnitZ());
      time.push_back(0.001 * i);
      gradient.emplace_back(0.1, 0.0, 0.3);  // its normal part is dropped
    }
  const auto lines = trace_chevron_lines(points, normals, time, gradient, 0.01, 100, 0.015);
  size_t long_lines = 0, covered = 0;
  std::set<size_t> seen;
  for (const auto& line : lines) {
    covered += line.size();
    for (size_t p : line) EXPECT_TRUE(seen.insert(p).second) << "point " << p << " on two lines";
    if (line.size() < 2) continue;
    ++long_lines;
    EXPECT_EQ(line.size(), 21u);
    for (size_t k = 1; k < line.size(); ++k) {
      EXPECT_NEAR(points[line[k]].y(), points[line[0]].y(), 1e-12);
      EXPECT_NEAR(points[line[k]].x() - points[line[k - 1]].x(), 0.01, 1e-12);
    }
  }
  EXPECT_EQ(long_lines, 11u);
  EXPECT_LE(covered, points.size());
}

TEST(FractureDetail, ChevronMarksOnACutBlockKeepBothHalvesFittingTogether) {
  // The slab crack of the fragment tests (|z| < s damaged, a plane at z = 0 between two halves), broken
  // from x = -L towards +x at 100 m/s.
  constexpr double kL = 0.05, kS = 0.005, kH = 0.01;
  const testing::DamagedBox box(kL, kS, [](const Vec3& p) { return std::abs(p.z()) < kS; });
  TriMesh domain = box_mesh(Vec3::Zero(), Vec3::Constant(kL), 2);
  domain.name = "block";
  CrackExtractionOptions co;
  co.grid.spacing = kH;
  const CrackExtraction crack = extract_crack(box.x, box.c_his, co);
  const Regions regions = find_regions(crack.diagram, crack.crack_face);
  FragmentOptions fo;
  fo.density = 2500;
  FragmentSet set = cut_fragments(domain, crack.diagram, regions, fo, "block.obj");
  ASSERT_EQ(set.fragments.size(), 2u);
  std::vector<ParticleDamage> damage(box.x.size());
  for (size_t p = 0; p < box.x.size(); ++p)
    if (box.c_his[p] >= 1) damage[p].tau = (box.x[p].x() + kL) / 100.0;

  FractureDetailOptions o;
  o.height = 2e-4;
  o.edge = 0.25 * kH;
  o.step = o.edge;
  o.radius = 2 * o.edge;
  o.grid = 0.5 * kH;
  const FragmentSet before = set;
  const FractureDetailReport r = add_fracture_detail(set, box.x, damage, o, 2500);
  std::printf("MEASURE detail: %zu crack vertices (%zu timed), %zu lines (%zu enhanced, longest %zu), %zu moved, "
              "max %.3g m, volume change %.3g, %.3f s\n",
              r.crack_vertices, r.timed_vertices, r.lines, r.enhanced_lines, r.longest_line, r.moved_vertices,
              r.max_displacement, set.volume_change(), r.seconds);
  EXPECT_EQ(r.timed_vertices, r.crack_vertices);  // the damaged band covers the whole crack plane
  EXPECT_GT(r.lines, 0u);
  EXPECT_GT(r.moved_vertices, r.crack_vertices / 2);
  EXPECT_GT(r.max_displacement, 0.0);
  // Both faces of the crack moved the same way: the halves' volumes still add up to the block's, to the
  // exact cutter's round-off, while each half's volume changed.
  EXPECT_LT(std::abs(set.volume_change()), 1e-9);
  for (size_t k = 0; k < set.fragments.size(); ++k) {
    const Fragment& f = set.fragments[k];
    EXPECT_TRUE(inspect_mesh(f.mesh).closed_manifold()) << f.mesh.name;
    // The marks moved volume across the crack plane (4 L^2 of it): more than a thousandth of the most.
    EXPECT_GT(std::abs(f.properties.volume - before.fragments[k].properties.volume),
              1e-3 * r.max_displacement * 4 * kL * kL)
        << f.mesh.name;
    // Crack faces are shaded smooth: each corner's normal faces the same side as its triangle.
    size_t backwards = 0;
    for (size_t t = 0; t < f.mesh.triangles.size(); ++t) {
      if (!f.crack_faces[t]) continue;
      const Tri& tri = f.mesh.triangles[t];
      const Vec3 face = (f.mesh.positions[static_cast<size_t>(tri[1])] - f.mesh.positions[static_cast<size_t>(tri[0])])
                            .cross(f.mesh.positions[static_cast<size_t>(tri[2])] - f.mesh.positions[static_cast<size_t>(tri[0])]);
      for (int k = 0; k < 3; ++k) backwards += f.mesh.normals[static_cast<size_t>(tri[k])].dot(face) <= 0;
    }
    EXPECT_EQ(backwards, 0u) << f.mesh.name;
    // The object's surface did not move: every vertex of an input triangle lies on the block's faces.
    for (size_t t = 0; t < f.mesh.triangles.size(); ++t) {
      if (f.crack_faces[t]) continue;
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(f.mesh.positions[static_cast<size_t>(f.mesh.triangles[t][k])].cwiseAbs().maxCoeff(), kL, 1e-12);
    }
  }
}

TEST(FractureDetail, RefinementStaysWithinItsTriangleBudget) {
  // An edge of 1 nm on a 0.1 m block would make about 1e16 triangles; the budget raises it instead.
  constexpr double kL = 0.05, kS = 0.005, kH = 0.01;
  const testing::DamagedBox box(kL, kS, [](const Vec3& p) { return std::abs(p.z()) < kS; });
  TriMesh domain = box_mesh(Vec3::Zero(), Vec3::Constant(kL), 2);
  CrackExtractionOptions co;
  co.grid.spacing = kH;
  const CrackExtraction crack = extract_crack(box.x, box.c_his, co);
  FragmentOptions fo;
  FragmentSet set = cut_fragments(domain, crack.diagram, find_regions(crack.diagram, crack.crack_face), fo, "block.obj");
  std::vector<ParticleDamage> damage(box.x.size());
  FractureDetailOptions o;
  o.height = 1e-4;
  o.edge = 1e-9;
  o.step = o.radius = o.grid = 0.0025;
  o.max_triangles = 2e4;
  const FractureDetailReport r = add_fracture_detail(set, box.x, damage, o, 1000);
  size_t triangles = 0;
  for (const Fragment& f : set.fragments)
    triangles += static_cast<size_t>(std::count(f.crack_faces.begin(), f.crack_faces.end(), 1));
  // Both faces of the 0.01 m^2 crack, 0.02 m^2 (the jittered Voronoi sheet is up to 2 % larger), in
  // triangles of an eighth of the equilateral one at the edge.
  EXPECT_NEAR(r.edge, std::sqrt(8 * 0.02 / (std::sqrt(3.0) / 4.0 * 2e4)), 0.02 * r.edge);
  std::printf("MEASURE budget 20000: edge %.4g m, %zu crack triangles\n", r.edge, triangles);
  EXPECT_LE(triangles, 20000u);
  EXPECT_GE(triangles, 20000u / 8);
}

TEST(FractureDetail, BadLengthsAreRefused) {
  FragmentSet set;
  FractureDetailOptions o;
  o.height = 1e-3;  // on, but without lengths
  EXPECT_THROW(add_fracture_detail(set, {}, {}, o, 1000), InputError);
}

}  // namespace
}  // namespace shellfrac::brittle
