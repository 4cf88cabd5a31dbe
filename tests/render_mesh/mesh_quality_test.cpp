#include "render_mesh/mesh_quality.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/seam_joins.hpp"

namespace shellfrac::render_mesh {
namespace {

// An n x n grid on [x0, x0 + 1] x [0, 1] with UVs, counter-clockwise quads.
PolyMesh square_grid(int n, double x0 = 0.0, const std::string& name = "square") {
  PolyMesh m;
  m.name = name;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.positions.emplace_back(x0 + i / double(n), j / double(n), 0.0);
      m.uvs.emplace_back(i / double(n), j / double(n));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = i + (n + 1) * j;
      m.add_face({a, a + 1, a + n + 2, a + n + 1});
    }
  return m;
}

PolyMesh deformed(const PolyMesh& rest, const Eigen::Matrix3d& F, const Vec3& shift = Vec3::Zero()) {
  PolyMesh m = rest;
  for (Vec3& x : m.positions) x = F * x + shift;
  return m;
}

TEST(EdgeStretch, AxisStretchGivesTheFactor) {
  const PolyMesh rest = square_grid(3);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 0) = 2.5, F(1, 1) = 0.5;
  const EdgeStretch s = max_edge_stretch(deformed(rest, F, Vec3(1, 2, 3)), rest);
  EXPECT_NEAR(s.ratio, 2.5, 1e-14);
  EXPECT_NEAR(s.rest_length, 1.0 / 3.0, 1e-15);
  EXPECT_GE(s.face, 0);
  // A rigid rotation stretches nothing.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_NEAR(max_edge_stretch(deformed(rest, R), rest.positions).ratio, 1.0, 1e-14);
}

TEST(EdgeStretch, ShortSidesAreMeasuredAgainstATenthOfTheMedianSide) {
  // A 4 x 4 grid (sides 0.25) plus one pentagon whose two corners are 1e-9 apart at rest, like a crack
  // vertex and its shadow. Moving one of them by 1e-4 (a basis mismatch far below any visible gap)
  // would read 1e5 against the rest length; against 0.1 x median = 0.025 it reads 0.004.
  PolyMesh rest = square_grid(4);
  const int a = static_cast<int>(rest.positions.size());
  rest.positions.push_back(Vec3(2.0, 0.0, 0.0));
  rest.positions.push_back(Vec3(2.0 + 1e-9, 0.0, 0.0));
  rest.positions.push_back(Vec3(2.25, 0.0, 0.0));
  rest.positions.push_back(Vec3(2.25, 0.25, 0.0));
  rest.positions.push_back(Vec3(2.0, 0.25, 0.0));
  for (int k = 0; k < 5; ++k) rest.uvs.emplace_back(0.0, 0.0);
  rest.add_face({a, a + 1, a + 2, a + 3, a + 4});
  PolyMesh current = rest;
  current.positions[static_cast<size_t>(a + 1)] += Vec3(0.0, 1e-4, 0.0);
  const EdgeStretch small = max_edge_stretch(current, rest);
  // The median side is 0.25; the worst side is now a grid side (ratio 1 up to the moved corner's
  // neighbour side, which changes by 1e-4 / 0.25 relative at most).
  EXPECT_NEAR(small.ratio, 1.0, 1e-3);
  // The same short side opened to 0.1 m (a strand across a gap) reads 0.1 / 0.025 = 4.
  current.positions[static_cast<size_t>(a + 1)] = rest.positions[static_cast<size_t>(a + 1)] + Vec3(0.0, 0.1, 0.0);
  const EdgeStretch gap = max_edge_stretch(current, rest);
  EXPECT_NEAR(gap.ratio, std::hypot(0.1, 1e-9) / (kShortSideFraction * 0.25), 1e-9);
  EXPECT_EQ(gap.face, current.num_faces() - 1);
  EXPECT_EQ(gap.corner, 0);
}

TEST(StrandArea, FacesOneNudgeWideAtRestAreDegenerate) {
  // A hexagon 1e-9 wide along a crack line (rest), whose corners then move apart by 1e-6 across it:
  // its least-squares map reads about 1000x, but it holds no material. A face 1e-5 wide (a shadow
  // offset) stretched 5x across is a strand.
  auto strip = [](double width, double opened) {
    std::vector<Vec3> rest, now;
    for (int k = 0; k < 3; ++k) rest.emplace_back(0.01 * k, 0.0, 0.0), now.emplace_back(0.01 * k, 0.0, 0.0);
    for (int k = 2; k >= 0; --k) rest.emplace_back(0.01 * k, width, 0.0), now.emplace_back(0.01 * k, opened, 0.0);
    return face_stretch(rest, now);
  };
  EXPECT_EQ(strip(1e-9, 1e-6), 0.0);
  EXPECT_NEAR(strip(1e-5, 5e-5), 5.0, 1e-9);
}

TEST(StrandArea, TinyFacesCountOnlyWhenTheyGrowPastTheFloor) {
  // A 4 x 4 grid (sides 0.25, floor 0.025) and a triangle of 1e-7 m at rest whose corners move by 1e-6:
  // its own map reads about 10x, but it is 1e-6 / 0.025 small; opened to 0.1 m it is a strand (4x).
  PolyMesh rest = square_grid(4);
  const int a = static_cast<int>(rest.positions.size());
  rest.positions.push_back(Vec3(2.0, 0.0, 0.0));
  rest.positions.push_back(Vec3(2.0 + 1e-7, 0.0, 0.0));
  rest.positions.push_back(Vec3(2.0, 1e-7, 0.0));
  for (int k = 0; k < 3; ++k) rest.uvs.emplace_back(0.0, 0.0);
  rest.add_face({a, a + 1, a + 2});
  PolyMesh current = rest;
  current.positions[static_cast<size_t>(a + 2)] = Vec3(2.0, 1e-6, 0.0);
  StrandStats s = strand_area(current, rest, 3.0);
  EXPECT_EQ(s.faces, 0);
  EXPECT_NEAR(s.max_principal_stretch, 1.0, 1e-12);  // the grid faces; the triangle reads 1e-6 / 0.025
  current.positions[static_cast<size_t>(a + 2)] = Vec3(2.0, 0.1, 0.0);
  s = strand_area(current, rest, 3.0);
  EXPECT_EQ(s.faces, 1);
  EXPECT_NEAR(s.max_principal_stretch, std::hypot(0.1, 1e-7) / (kShortSideFraction * 0.25), 1e-9);
}

TEST(PrincipalStretch, SimpleShearHasTheClosedForm) {
  // x' = x + g y: F = [[1, g], [0, 1]], singular values (sqrt(g^2 + 4) +- g) / 2.
  const PolyMesh rest = square_grid(1);
  for (const double g : {0.0, 0.5, 2.7, 10.0}) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    F(0, 1) = g;
    const PolyMesh current = deformed(rest, F);
    const double exact = 0.5 * (g + std::sqrt(g * g + 4.0));
    const StrandStats s = strand_area(current, rest, 3.0);
    EXPECT_NEAR(s.max_principal_stretch, exact, 1e-13 * exact) << g;
    // The edges of the square: the vertical ones stretch by sqrt(1 + g^2), less than the material does.
    EXPECT_NEAR(max_edge_stretch(current, rest).ratio, std::sqrt(1.0 + g * g), 1e-13 * exact) << g;
    // Shear keeps the area, so the strand area is the whole square once the threshold is passed.
    EXPECT_EQ(s.faces, exact > 3.0 ? 1 : 0) << g;
    EXPECT_NEAR(s.area, exact > 3.0 ? 1.0 : 0.0, 1e-14) << g;
  }
  // g = 2.7: a strand by principal stretch (3.045) although no render edge reaches 3 (2.879).
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 1) = 2.7;
  EXPECT_LT(max_edge_stretch(deformed(rest, F), rest).ratio, 3.0);
  EXPECT_EQ(strand_area(deformed(rest, F), rest).faces, 1);
}

TEST(PrincipalStretch, ThinTriangleStretchedAcrossAndRotatedIn3D) {
  // A needle (height 0.01) stretched 10x across: its sides barely lengthen, the material stretches 10x.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, 0.01, 0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Vec3(0.3, -1, 2).normalized()).toRotationMatrix();
  auto map = [&](const Vec3& x) { return Vec3(R * Vec3(x.x(), 10 * x.y(), 0) + Vec3(4, 5, 6)); };
  EXPECT_NEAR(principal_stretch(a, b, c, map(a), map(b), map(c)), 10.0, 1e-12);
  const double side_ratio = (map(c) - map(a)).norm() / (c - a).norm();
  EXPECT_LT(side_ratio, 1.02);  // 1.0196
  EXPECT_DOUBLE_EQ(principal_stretch(a, b, Vec3(2, 0, 0), a, b, c), 0.0);  // no rest area
}

// A pentagon with two corners 1e-5 apart (a crack's shadow vertices), moved rigidly plus a small wobble
// of one of the close corners: the face is not stretched, although the thin triangle between the close
// corners is (its own map amplifies the 1e-4 wobble over a 1e-5 height).
TEST(StrandArea, ThinSubTrianglesDoNotMakeAStrand) {
  const std::vector<Vec3> rest{{1e-5, 0, 0}, {0.01, 0, 0}, {0.01, 0.01, 0}, {0, 0.01, 0}, {0, 0, 0}};
  std::vector<Vec3> current = rest;
  for (Vec3& x : current) x = Vec3(x.y(), -x.x(), 0.2);  // rotated and lifted
  current[0] += Vec3(0, 0, 1e-4);
  EXPECT_GT(principal_stretch(rest[0], rest[3], rest[4], current[0], current[3], current[4]), 5.0);
  EXPECT_NEAR(face_stretch(rest, current), 1.0, 0.01);
  // Exact for an affine map of the whole polygon: stretch 4 along x.
  for (size_t k = 0; k < rest.size(); ++k) current[k] = Vec3(4 * rest[k].x(), rest[k].y(), 0);
  EXPECT_NEAR(face_stretch(rest, current), 4.0, 1e-12);
}

TEST(StrandArea, ThresholdCountsOnlyStretchedFacesWithTheirCurrentArea) {
  // Stretch only the right column of a 2 x 2 grid by 4 along x: 2 faces, current area 2 x (0.5 * 4 * 0.5).
  const PolyMesh rest = square_grid(2);
  PolyMesh current = rest;
  for (Vec3& x : current.positions)
    if (x.x() > 0.5) x.x() = 0.5 + 4.0 * (x.x() - 0.5);
  const StrandStats s = strand_area(current, rest.positions, 3.0);
  EXPECT_EQ(s.faces, 2);
  EXPECT_NEAR(s.area, 2.0, 1e-14);
  EXPECT_NEAR(s.max_principal_stretch, 4.0, 1e-14);
  EXPECT_EQ(strand_area(current, rest.positions, 4.5).faces, 0);
  EXPECT_THROW(strand_area(current, std::vector<Vec3>(3)), std::invalid_argument);
  PolyMesh other = rest;
  other.face_vertices[0] = 1;
  EXPECT_THROW(max_edge_stretch(current, other), std::invalid_argument);
}

TEST(PieceStats, ExplicitJoinsMakeOnePieceAcrossMeshes) {
  const std::vector<PolyMesh> meshes{square_grid(2, 0.0, "left"), square_grid(2, 1.0, "right")};
  const PieceStats apart = piece_stats(meshes, {}, 0.01);
  EXPECT_EQ(apart.pieces, 2);
  EXPECT_EQ(apart.slivers, 0);
  ASSERT_EQ(apart.component_area.size(), 2u);
  EXPECT_NEAR(apart.component_area[0], 1.0, 1e-15);
  EXPECT_NEAR(apart.piece_area, 2.0, 1e-14);
  // The right side of "left" (vertices 2, 5, 8) is the left side of "right" (0, 3, 6).
  const std::vector<VertexJoin> joins{{0, 2, 1, 0}, {0, 5, 1, 3}, {0, 8, 1, 6}};
  const PieceStats joined = piece_stats(meshes, joins, 0.01);
  EXPECT_EQ(joined.pieces, 1);
  EXPECT_NEAR(joined.component_area[0], 2.0, 1e-14);
  for (const auto& labels : joined.face_label)
    for (int l : labels) EXPECT_EQ(l, 0);
  EXPECT_EQ(piece_stats(meshes, {joins[1]}, 0.01).pieces, 1);  // one join is enough
  EXPECT_THROW(piece_stats(meshes, {{0, 9, 1, 0}}, 0.01), std::invalid_argument);
  EXPECT_THROW(piece_stats(meshes, {{2, 0, 1, 0}}, 0.01), std::invalid_argument);
}

TEST(PieceStats, TinyTriangleIsASliverWithItsExactArea) {
  PolyMesh m = square_grid(1);
  const int base = m.num_vertices();
  const double leg_x = std::ldexp(1.0, -10), leg_y = std::ldexp(1.0, -12);  // exact binary fractions
  m.positions.insert(m.positions.end(), {{2, 0, 0}, {2 + leg_x, 0, 0}, {2, leg_y, 0}});
  m.uvs.insert(m.uvs.end(), {{0.9, 0.9}, {0.95, 0.9}, {0.9, 0.95}});
  m.add_face({base, base + 1, base + 2});
  m.positions.emplace_back(5, 5, 5);  // a point primitive: no area, not a piece
  m.add_face({base + 3});
  const PieceStats s = piece_stats({m}, {}, 1e-4);
  EXPECT_EQ(s.pieces, 1);
  EXPECT_EQ(s.slivers, 1);
  EXPECT_DOUBLE_EQ(s.sliver_area, 0.5 * leg_x * leg_y);  // 2^-23 m^2
  EXPECT_NEAR(s.piece_area, 1.0, 1e-15);
  EXPECT_EQ(s.face_label[0], (std::vector<int>{0, 1, -1}));
  EXPECT_EQ(s.component_is_sliver, (std::vector<unsigned char>{0, 1}));
}

TEST(PieceStats, CrackedSheetAndSeamJoins) {
  // Two unit patches side by side, a crack along v = 0.5 through both: 2 pieces; each patch alone is cut
  // in 2, and with the crack in the left patch only the right one holds the halves together.
  CrackedTessellationSettings settings;
  settings.resolution_u = 5;
  settings.resolution_v = 6;
  auto patch = [&](double x0, const std::string& name, bool cracked) {
    std::vector<CrackSegment2> crack;
    if (cracked) crack.push_back({{0.0, 0.5}, {1.0, 0.5}});
    const ParameterMesh sep = separate_crack_vertices(split_parameter_grid({}, crack, settings), settings.shadow_offset);
    return cracked_tessellation(sep, {}, [x0](const Vec2& uv) { return Vec3(x0 + uv.x(), uv.y(), 0.0); }, name);
  };
  const std::vector<PolyMesh> meshes{patch(0.0, "a", true), patch(1.0, "b", true)};
  const auto a = side_vertices(meshes[0], UvSide::u_max, 3e-5), b = side_vertices(meshes[1], UvSide::u_min, 3e-5);
  // 6 grid vertices off the crack on the side, and the 2 shadows (Dv / sqrt 2 off the side) of the
  // crack vertex (1, 0.5), which no face uses any more.
  EXPECT_EQ(a.size(), 8u);
  const PieceStats cut = piece_stats(meshes, seam_joins(0, a, 1, b, {0.5}, 0.01), 1e-3);
  EXPECT_EQ(cut.pieces, 2);
  EXPECT_EQ(cut.slivers, 0);
  // Each piece is 1 m^2 less a shadow strip of width about Dv = 1e-5 along the 2 m crack.
  EXPECT_NEAR(cut.component_area[0], 1.0, 3e-5);
  EXPECT_NEAR(cut.component_area[1], 1.0, 3e-5);
  EXPECT_NEAR(cut.piece_area, 2.0, 6e-5);
  EXPECT_EQ(piece_stats(meshes, {}, 1e-3).pieces, 4);
  const std::vector<PolyMesh> half{patch(0.0, "a", true), patch(1.0, "b", false)};
  const auto b_intact = side_vertices(half[1], UvSide::u_min, 3e-5);
  EXPECT_EQ(b_intact.size(), 7u);
  EXPECT_EQ(piece_stats(half, seam_joins(0, a, 1, b_intact, {0.5}, 0.01), 1e-3).pieces, 1);
}

TEST(SeamJoins, NearestVertexNotAcrossACrackAndWithinTheGap) {
  // Non-conforming sides: a's vertex at 0.49 is nearest to b's at 0.51, but the crack at 0.5 lies between.
  const std::vector<SeamVertex> a{{10, 0.49}, {11, 0.7}, {12, 0.99}}, b{{20, 0.3}, {21, 0.51}, {22, 0.75}};
  const auto joins = seam_joins(0, a, 1, b, {0.5}, 0.2);
  ASSERT_EQ(joins.size(), 2u);  // 0.99 is 0.24 from its nearest: beyond the gap
  EXPECT_EQ(joins[0].vertex_a, 10);
  EXPECT_EQ(joins[0].vertex_b, 20);
  EXPECT_EQ(joins[1].vertex_a, 11);
  EXPECT_EQ(joins[1].vertex_b, 22);
  const auto uncut = seam_joins(0, a, 1, b, {}, 0.2);
  EXPECT_EQ(uncut[0].vertex_b, 21);
  EXPECT_EQ(uncut[0].mesh_a, 0);
  EXPECT_EQ(uncut[0].mesh_b, 1);
}

}  // namespace
}  // namespace shellfrac::render_mesh
