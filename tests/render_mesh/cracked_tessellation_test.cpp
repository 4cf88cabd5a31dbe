#include "render_mesh/cracked_tessellation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>

#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "nurbs/patch_builders.hpp"
#include "render_mesh/surface_tessellation.hpp"

namespace shellfrac::render_mesh {
namespace {

const double kPi = std::acos(-1.0);
const ParameterDomain kUnit{0.0, 1.0, 0.0, 1.0};

CrackedTessellationSettings grid(int r, int s, double shadow = 1e-5) {
  CrackedTessellationSettings settings;
  settings.resolution_u = r;
  settings.resolution_v = s;
  settings.shadow_offset = shadow;
  return settings;
}

std::vector<CrackSegment2> polyline(const std::vector<Vec2>& points, bool closed = false) {
  std::vector<CrackSegment2> segments;
  for (size_t k = 0; k + 1 < points.size(); ++k) segments.push_back({points[k], points[k + 1]});
  if (closed) segments.push_back({points.back(), points.front()});
  return segments;
}

double total_area(const ParameterMesh& m) {
  double sum = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) sum += signed_area(m, f);
  return sum;
}

double smallest_face_area(const ParameterMesh& m) {
  double smallest = 1e300;
  for (int f = 0; f < m.num_faces(); ++f) smallest = std::min(smallest, signed_area(m, f));
  return smallest;
}

// Fragment label of every face: faces sharing a vertex index are one fragment.
std::vector<int> face_labels(const ParameterMesh& m) {
  std::vector<int> parent(static_cast<size_t>(m.num_vertices()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)];
    return x;
  };
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = m.face_offsets[static_cast<size_t>(f)]; k < m.face_offsets[static_cast<size_t>(f) + 1]; ++k)
      parent[static_cast<size_t>(find(m.face_vertices[static_cast<size_t>(k)]))] =
          find(m.face_vertices[static_cast<size_t>(m.face_offsets[static_cast<size_t>(f)])]);
  std::vector<int> labels;
  for (int f = 0; f < m.num_faces(); ++f)
    labels.push_back(find(m.face_vertices[static_cast<size_t>(m.face_offsets[static_cast<size_t>(f)])]));
  return labels;
}

// Winding number of face f of `m` around p (1 inside a counter-clockwise polygon, also next to slits).
int winding_number(const ParameterMesh& m, int f, const Vec2& p) {
  int winding = 0;
  const int begin = m.face_offsets[static_cast<size_t>(f)], end = m.face_offsets[static_cast<size_t>(f) + 1];
  for (int k = begin; k < end; ++k) {
    const Vec2 a = m.uv[static_cast<size_t>(m.face_vertices[static_cast<size_t>(k)])] - p;
    const Vec2 b = m.uv[static_cast<size_t>(m.face_vertices[static_cast<size_t>(k + 1 < end ? k + 1 : begin)])] - p;
    const double side = a.x() * b.y() - a.y() * b.x();
    if (a.y() <= 0.0 && b.y() > 0.0 && side > 0.0) ++winding;
    if (a.y() > 0.0 && b.y() <= 0.0 && side < 0.0) --winding;
  }
  return winding;
}

struct Split {
  ParameterMesh split, separated;
};

Split cut(const std::vector<CrackSegment2>& crack, int r, int s, double shadow = 1e-5,
          const ParameterDomain& domain = kUnit) {
  Split result;
  result.split = split_parameter_grid(domain, crack, grid(r, s, shadow));
  result.separated = separate_crack_vertices(result.split, shadow);
  return result;
}

// Checks shared by every cracked case: area conserved to 1e-12, every face counter-clockwise, the
// separated mesh keeps the faces, and no face repeats a vertex after separation.
void expect_valid(const Split& m, double area) {
  EXPECT_NEAR(total_area(m.split), area, 1e-12);
  EXPECT_GT(smallest_face_area(m.split), 0.0);
  ASSERT_EQ(m.separated.num_faces(), m.split.num_faces());
  for (int f = 0; f < m.separated.num_faces(); ++f) {
    std::set<int> corners;
    for (int k = m.separated.face_offsets[static_cast<size_t>(f)]; k < m.separated.face_offsets[static_cast<size_t>(f) + 1]; ++k)
      corners.insert(m.separated.face_vertices[static_cast<size_t>(k)]);
    EXPECT_EQ(static_cast<int>(corners.size()),
              m.separated.face_offsets[static_cast<size_t>(f) + 1] - m.separated.face_offsets[static_cast<size_t>(f)])
        << "face " << f;
  }
}

TEST(CrackedTessellation, SurfaceAreaOfQuadsAndTriangles) {
  // A unit square tilted out of plane (area 1) and a right triangle with legs 2 and 3 (area 3).
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0.6, 0.8}, {0, 0.6, 0.8}, {5, 0, 0}, {7, 0, 0}, {5, 3, 0}};
  m.add_face({0, 1, 2, 3});
  m.add_face({4, 5, 6});
  EXPECT_NEAR(surface_area(m), 4.0, 1e-14);
}

TEST(CrackedTessellation, WithoutCrackEqualsTheUncrackedGrid) {
  const ParameterDomain domain{0.5, 2.5, -1.0, 2.0};
  const Split m = cut({}, 5, 3, 1e-5, domain);
  ASSERT_EQ(m.split.num_vertices(), 6 * 4);
  ASSERT_EQ(m.split.num_faces(), 5 * 3);
  for (int j = 0, f = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i, ++f) {
      const int a = i + 6 * j;
      const std::vector<int> expected{a, a + 1, a + 7, a + 6};
      const std::vector<int> face(m.split.face_vertices.begin() + m.split.face_offsets[static_cast<size_t>(f)],
                                  m.split.face_vertices.begin() + m.split.face_offsets[static_cast<size_t>(f) + 1]);
      EXPECT_EQ(face, expected);
    }
  EXPECT_EQ(m.separated.uv, m.split.uv);
  EXPECT_EQ(m.separated.face_vertices, m.split.face_vertices);
  EXPECT_NEAR(total_area(m.split), 2.0 * 3.0, 1e-12);
  EXPECT_EQ(count_components(m.separated), 1);
}

TEST(CrackedTessellation, WithoutCrackMatchesTessellateOnANurbsSurface) {
  const auto surface = nurbs::cylinder_segment(0.5, 2.0, 3.14159265358979, 6, 4);
  const PolyMesh reference = tessellate(surface, 7, 5, "tube");
  const ParameterDomain domain{surface.knots_u().domain_begin(), surface.knots_u().domain_end(),
                               surface.knots_v().domain_begin(), surface.knots_v().domain_end()};
  const PolyMesh mesh = cracked_tessellation(
      domain, {}, grid(7, 5), [&](const Vec2& uv) { return surface.evaluate(uv.x(), uv.y()).x; }, "tube");
  ASSERT_EQ(mesh.num_vertices(), reference.num_vertices());
  EXPECT_EQ(mesh.face_offsets, reference.face_offsets);
  EXPECT_EQ(mesh.face_vertices, reference.face_vertices);
  double worst_position = 0.0, worst_uv = 0.0, worst_normal = 0.0;
  for (int k = 0; k < mesh.num_vertices(); ++k) {
    worst_position = std::max(worst_position, (mesh.positions[static_cast<size_t>(k)] - reference.positions[static_cast<size_t>(k)]).norm());
    worst_uv = std::max(worst_uv, (mesh.uvs[static_cast<size_t>(k)] - reference.uvs[static_cast<size_t>(k)]).norm());
    // Averaged polygon normals approximate the surface normal to O(h^2) on this coarse grid.
    worst_normal = std::max(worst_normal, (mesh.normals[static_cast<size_t>(k)] - reference.normals[static_cast<size_t>(k)]).norm());
  }
  EXPECT_EQ(worst_position, 0.0);
  EXPECT_LE(worst_uv, 1e-15);
  EXPECT_LE(worst_normal, 0.25);
  EXPECT_EQ(count_components(mesh), 1);
}

TEST(CrackedTessellation, StraightCutSeparatesTwoFragmentsWithoutSharedVertices) {
  const double v_cut = 0.5 + 0.013;
  const Split m = cut({{Vec2(-0.2, v_cut), Vec2(1.3, v_cut)}}, 8, 8);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 2);
  // 8 cut quads become 16 polygons.
  EXPECT_EQ(m.split.num_faces(), 64 + 8);
  const std::vector<int> labels = face_labels(m.separated);
  std::map<int, std::set<int>> vertices_of;
  for (int f = 0; f < m.separated.num_faces(); ++f) {
    int below = 0, above = 0;
    for (int k = m.separated.face_offsets[static_cast<size_t>(f)]; k < m.separated.face_offsets[static_cast<size_t>(f) + 1]; ++k) {
      const int v = m.separated.face_vertices[static_cast<size_t>(k)];
      vertices_of[labels[static_cast<size_t>(f)]].insert(v);
      (m.separated.uv[static_cast<size_t>(v)].y() < v_cut ? below : above)++;
    }
    EXPECT_TRUE(below == 0 || above == 0) << "face " << f << " straddles the cut";
  }
  ASSERT_EQ(vertices_of.size(), 2u);
  std::vector<int> common;
  std::set_intersection(vertices_of.begin()->second.begin(), vertices_of.begin()->second.end(),
                        vertices_of.rbegin()->second.begin(), vertices_of.rbegin()->second.end(),
                        std::back_inserter(common));
  EXPECT_TRUE(common.empty());
}

TEST(CrackedTessellation, DiagonalCut) {
  const Split m = cut({{Vec2(0.0, 0.1), Vec2(1.0, 0.83)}}, 7, 9);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 2);
  // Area below the line: trapezoid.
  const std::vector<int> labels = face_labels(m.separated);
  std::map<int, double> area;
  for (int f = 0; f < m.split.num_faces(); ++f) area[labels[static_cast<size_t>(f)]] += signed_area(m.split, f);
  std::vector<double> areas;
  for (const auto& entry : area) areas.push_back(entry.second);
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], 0.5 * (0.1 + 0.83), 1e-12);
}

TEST(CrackedTessellation, CutThroughGridVerticesAndAlongAQuadEdge) {
  // Along the grid line v = 0.25 up to the grid vertex (0.5, 0.25), then diagonally through the grid
  // vertex (0.75, 0.5) to the grid vertex (1, 0.75).
  const Split m = cut(polyline({Vec2(0.0, 0.25), Vec2(0.5, 0.25), Vec2(1.0, 0.75)}), 4, 4);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 2);
  EXPECT_EQ(m.split.num_vertices(), 25);  // the crack adds no vertex: it only uses grid vertices
  EXPECT_EQ(m.split.num_faces(), 16 + 2);
  int on_crack = 0;
  for (unsigned char c : m.split.on_crack) on_crack += c;
  EXPECT_EQ(on_crack, 3 + 2);
}

TEST(CrackedTessellation, CrackVerticesWithMedialAxisRoundOffStillHitTheGrid) {
  // The same crack as above at 64 x 64 quads, its vertices off by 2e-9 (the round-off of crack vertices
  // from the Voronoi medial axis; 1.3e-7 of a quad side). It must still run along the grid line and
  // through the grid vertices: no face thinner than a quad's 1e-6, the same faces as the exact crack.
  const double d = 2e-9;
  const Split exact = cut(polyline({Vec2(0.0, 0.25), Vec2(0.5, 0.25), Vec2(1.0, 0.75)}), 64, 64);
  const Split noisy = cut(polyline({Vec2(0.0, 0.25 + d), Vec2(0.5 - d, 0.25 + d), Vec2(0.75 + d, 0.5 - d),
                                    Vec2(1.0, 0.75 + d)}),
                          64, 64);
  expect_valid(noisy, 1.0);
  const double quad_area = 1.0 / (64.0 * 64.0);
  EXPECT_GT(smallest_face_area(noisy.split), 1e-6 * quad_area);
  EXPECT_EQ(noisy.split.num_faces(), exact.split.num_faces());
  EXPECT_EQ(noisy.split.num_vertices(), exact.split.num_vertices());
  EXPECT_EQ(count_components(noisy.separated), 2);
}

TEST(CrackedTessellation, CrackAlongAQuadEdgeOnlySeparatesItsLength) {
  // Through the whole patch along v = 0.5: two fragments; a piece on the patch boundary cuts nothing.
  const Split full = cut({{Vec2(0.0, 0.5), Vec2(1.0, 0.5)}, {Vec2(0.0, 0.0), Vec2(1.0, 0.0)}}, 4, 4);
  expect_valid(full, 1.0);
  EXPECT_EQ(count_components(full.separated), 2);
  EXPECT_EQ(full.split.num_faces(), 16);
  const Split half = cut({{Vec2(0.0, 0.5), Vec2(0.6, 0.5)}}, 4, 4);
  expect_valid(half, 1.0);
  EXPECT_EQ(count_components(half.separated), 1);
}

TEST(CrackedTessellation, CrackEndingInsideAQuadIsASlit) {
  const Vec2 tip(0.43, 0.55);
  const Split m = cut({{Vec2(-0.1, 0.55), tip}}, 4, 4);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 1);
  // Every quad stays one face; the one holding the tip walks around the slit and through the tip once.
  EXPECT_EQ(m.split.num_faces(), 16 + 1);
  int tip_corners = 0;
  for (int v : m.separated.face_vertices)
    if ((m.split.uv[static_cast<size_t>(m.separated.source_vertex[static_cast<size_t>(v)])] - tip).norm() < 1e-15) {
      ++tip_corners;
      // The tip's shadow lies ahead of the tip, beyond the end of the slit.
      EXPECT_NEAR(m.separated.uv[static_cast<size_t>(v)].x() - tip.x(), 1e-5, 1e-15);
      EXPECT_NEAR(m.separated.uv[static_cast<size_t>(v)].y(), tip.y(), 1e-15);
    }
  EXPECT_EQ(tip_corners, 1);
}

TEST(CrackedTessellation, YJunctionGivesThreeFragments) {
  const Vec2 centre(0.52, 0.47);
  const Split m = cut({{centre, Vec2(0.0, 0.8)}, {centre, Vec2(1.0, 0.9)}, {centre, Vec2(0.6, 0.0)}}, 6, 6);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 3);
  // Thesis Fig. 4.17: the junction gets one shadow per polygon around it, here three.
  int junction_shadows = 0;
  for (int v = 0; v < m.separated.num_vertices(); ++v)
    if ((m.split.uv[static_cast<size_t>(m.separated.source_vertex[static_cast<size_t>(v)])] - centre).norm() < 1e-15)
      ++junction_shadows;
  EXPECT_EQ(junction_shadows, 3);
}

TEST(CrackedTessellation, ClosedLoopCutsOutItsPolygon) {
  const int n = 32;
  const double radius = 0.3;
  std::vector<Vec2> circle;
  for (int k = 0; k < n; ++k)
    circle.emplace_back(0.5 + radius * std::cos(2 * kPi * k / n), 0.5 + radius * std::sin(2 * kPi * k / n));
  const double shadow = 1e-5;
  const Split m = cut(polyline(circle, true), 6, 6, shadow);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 2);
  const double polygon_area = 0.5 * n * radius * radius * std::sin(2 * kPi / n);
  const std::vector<int> labels = face_labels(m.separated);
  std::map<int, double> split_area, separated_area, perimeter;
  for (int f = 0; f < m.split.num_faces(); ++f) {
    split_area[labels[static_cast<size_t>(f)]] += signed_area(m.split, f);
    separated_area[labels[static_cast<size_t>(f)]] += signed_area(m.separated, f);
    for (int k = m.split.face_offsets[static_cast<size_t>(f)]; k < m.split.face_offsets[static_cast<size_t>(f) + 1]; ++k) {
      const int next = k + 1 < m.split.face_offsets[static_cast<size_t>(f) + 1] ? k + 1 : m.split.face_offsets[static_cast<size_t>(f)];
      perimeter[labels[static_cast<size_t>(f)]] +=
          (m.split.uv[static_cast<size_t>(m.split.face_vertices[static_cast<size_t>(next)])] -
           m.split.uv[static_cast<size_t>(m.split.face_vertices[static_cast<size_t>(k)])]).norm();
    }
  }
  const auto inner = std::min_element(split_area.begin(), split_area.end(),
                                      [](const auto& a, const auto& b) { return a.second < b.second; });
  EXPECT_NEAR(inner->second, polygon_area, 1e-12);
  // Moving corners by Dv changes a polygon's area by at most Dv times its perimeter.
  EXPECT_LE(std::abs(separated_area[inner->first] - polygon_area), shadow * perimeter[inner->first]);
  EXPECT_LT(separated_area[inner->first], polygon_area);  // shadows move inwards
}

TEST(CrackedTessellation, CracksInsideOneQuadAreBridgedToItsBoundary) {
  // A slit and a small triangle floating in quad (0, 0) of a 2 x 2 grid, and a cross in quad (1, 1).
  std::vector<CrackSegment2> crack{{Vec2(0.1, 0.2), Vec2(0.2, 0.3)}};
  const auto triangle = polyline({Vec2(0.25, 0.1), Vec2(0.4, 0.12), Vec2(0.3, 0.35)}, true);
  crack.insert(crack.end(), triangle.begin(), triangle.end());
  crack.push_back({Vec2(0.6, 0.6), Vec2(0.9, 0.9)});
  crack.push_back({Vec2(0.6, 0.9), Vec2(0.9, 0.6)});
  const Split m = cut(crack, 2, 2);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 2);  // the triangle falls out; slit and cross do not cut through
  const double triangle_area = 0.5 * std::abs((0.4 - 0.25) * (0.35 - 0.1) - (0.12 - 0.1) * (0.3 - 0.25));
  const std::vector<int> labels = face_labels(m.separated);
  std::map<int, double> area;
  for (int f = 0; f < m.split.num_faces(); ++f) area[labels[static_cast<size_t>(f)]] += signed_area(m.split, f);
  double smallest = 1.0;
  for (const auto& entry : area) smallest = std::min(smallest, entry.second);
  EXPECT_NEAR(smallest, triangle_area, 1e-12);
}

TEST(CrackedTessellation, ShadowsAreDvFromTheirCrackVertexAndInsideTheirSector) {
  const double shadow = 1e-5;
  const Vec2 centre(0.52, 0.47);
  std::vector<CrackSegment2> crack{{centre, Vec2(0.0, 0.8)}, {centre, Vec2(1.0, 0.9)}, {centre, Vec2(0.6, 0.0)},
                                   {Vec2(0.1, 0.1), Vec2(0.33, 0.2)}};
  const Split m = cut(crack, 5, 5, shadow);
  // The faces around each shadow (its sector: one side of the crack at that vertex).
  std::map<int, std::set<int>> faces_of;
  for (int f = 0; f < m.separated.num_faces(); ++f)
    for (int k = m.separated.face_offsets[static_cast<size_t>(f)]; k < m.separated.face_offsets[static_cast<size_t>(f) + 1]; ++k)
      if (m.separated.on_crack[static_cast<size_t>(m.separated.face_vertices[static_cast<size_t>(k)])])
        faces_of[m.separated.face_vertices[static_cast<size_t>(k)]].insert(f);
  double worst_distance = 0.0;
  int single_polygon = 0;
  for (const auto& [v, faces] : faces_of) {
    const Vec2& original = m.split.uv[static_cast<size_t>(m.separated.source_vertex[static_cast<size_t>(v)])];
    const Vec2& moved = m.separated.uv[static_cast<size_t>(v)];
    worst_distance = std::max(worst_distance, std::abs((moved - original).norm() - shadow));
    // Inside the union of the sector's polygons (before the move), away from their edges.
    int winding = 0;
    for (int f : faces) winding += winding_number(m.split, f, moved);
    EXPECT_EQ(winding, 1) << "shadow " << v;
    if (faces.size() == 1) {
      ++single_polygon;
      EXPECT_EQ(winding_number(m.split, *faces.begin(), moved), 1);
    }
  }
  EXPECT_GT(faces_of.size(), 30u);
  EXPECT_GT(single_polygon, 5);
  // Exact up to rounding of coordinates of order 1: a few ulp of 1.0 (1e-11 relative to Dv).
  EXPECT_LE(worst_distance, 1e-15);
}

TEST(CrackedTessellation, CrossingPointGetsOneShadowPerSide) {
  // A straight cut crossing the vertical quad edge u = 0.5: four polygons meet there, two on each
  // side; each side keeps one shared vertex so that the fragment stays watertight.
  const Split m = cut({{Vec2(0.0, 0.3), Vec2(1.0, 0.4)}}, 2, 2);
  const Vec2 crossing(0.5, 0.35);
  std::vector<int> shadows;
  for (int v = 0; v < m.separated.num_vertices(); ++v)
    if ((m.split.uv[static_cast<size_t>(m.separated.source_vertex[static_cast<size_t>(v)])] - crossing).norm() < 1e-15)
      shadows.push_back(v);
  ASSERT_EQ(shadows.size(), 2u);
  // Bisector of the two 180 degree sectors: perpendicular to the crack.
  const Vec2 normal = Vec2(-0.1, 1.0).normalized();
  for (int v : shadows)
    EXPECT_NEAR(std::abs((m.separated.uv[static_cast<size_t>(v)] - crossing).dot(normal)), 1e-5, 1e-15);
}

TEST(CrackedTessellation, AffineEvaluatorScalesAreasByTheJacobian) {
  Eigen::Matrix3d A;
  A << 2.0, 0.5, 0.0, -0.3, 1.5, 0.0, 0.7, 0.2, 1.0;
  const Vec3 b(0.1, -2.0, 3.0);
  const ParameterDomain domain{-1.0, 1.0, 2.0, 3.5};
  const Vec2 centre(0.1, 2.7);
  const std::vector<CrackSegment2> crack{{centre, Vec2(-1.0, 3.2)}, {centre, Vec2(1.0, 3.4)}, {centre, Vec2(0.2, 2.0)}};
  const CrackedTessellationSettings settings = grid(9, 6);
  const ParameterMesh separated =
      separate_crack_vertices(split_parameter_grid(domain, crack, settings), settings.shadow_offset);
  const PolyMesh mesh = cracked_tessellation(
      separated, domain, [&](const Vec2& uv) { return Vec3(A * Vec3(uv.x(), uv.y(), 0.0) + b); }, "plate");
  const Vec3 jacobian_normal = A.col(0).cross(A.col(1));
  const double scale = jacobian_normal.norm();
  double world = 0.0, parameter = 0.0, worst_normal = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Vec3 area = Vec3::Zero();
    for (int k = mesh.face_offsets[static_cast<size_t>(f)]; k < mesh.face_offsets[static_cast<size_t>(f) + 1]; ++k) {
      const int next = k + 1 < mesh.face_offsets[static_cast<size_t>(f) + 1] ? k + 1 : mesh.face_offsets[static_cast<size_t>(f)];
      area += 0.5 * mesh.positions[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])].cross(
                        mesh.positions[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(next)])]);
    }
    EXPECT_GT(area.dot(jacobian_normal), 0.0);  // counter-clockwise seen from du x dv
    world += area.norm();
    parameter += signed_area(separated, f);
  }
  EXPECT_NEAR(world, scale * parameter, 1e-9);
  EXPECT_NEAR(parameter, 2.0 * 1.5, 1e-3);
  for (const Vec3& n : mesh.normals) worst_normal = std::max(worst_normal, (n - jacobian_normal / scale).norm());
  EXPECT_LE(worst_normal, 1e-12);
  for (const Vec2& uv : mesh.uvs) {
    EXPECT_GE(uv.x(), 0.0);
    EXPECT_LE(uv.x(), 1.0);
    EXPECT_GE(uv.y(), 0.0);
    EXPECT_LE(uv.y(), 1.0);
  }
  EXPECT_EQ(count_components(mesh), 3);
}

TEST(CrackedTessellation, DegenerateSegmentsAreIgnored) {
  const std::vector<CrackSegment2> crack{{Vec2(0.3, 0.3), Vec2(0.3, 0.3)},    // zero length
                                         {Vec2(1.5, 0.2), Vec2(2.0, 0.9)},    // outside
                                         {Vec2(0.0, -0.5), Vec2(1.0, -0.1)},  // outside, below
                                         {Vec2(1.0, 0.0), Vec2(1.0, 1.0)},    // on the patch boundary
                                         {Vec2(0.2, 0.2), Vec2(0.2 + 1e-13, 0.2)}};
  const Split m = cut(crack, 3, 3);
  EXPECT_EQ(m.split.num_vertices(), 16);
  EXPECT_EQ(m.split.num_faces(), 9);
  EXPECT_NEAR(total_area(m.split), 1.0, 1e-12);
  EXPECT_EQ(count_components(m.separated), 1);
  const std::vector<CrackSegment2> not_finite{{Vec2(0.1, 0.1), Vec2(std::nan(""), 0.5)}};
  EXPECT_EQ(cut(not_finite, 3, 3).split.num_faces(), 9);
}

TEST(CrackedTessellation, CrossingAndOverlappingSegments) {
  // An X through the whole patch plus a segment lying on part of one arm: four fragments.
  const std::vector<CrackSegment2> crack{{Vec2(0.0, 0.03), Vec2(1.0, 0.97)},
                                         {Vec2(0.0, 0.91), Vec2(1.0, 0.05)},
                                         {Vec2(0.25, 0.265), Vec2(0.75, 0.735)}};
  const Split m = cut(crack, 5, 4);
  expect_valid(m, 1.0);
  EXPECT_EQ(count_components(m.separated), 4);
}

// Fragments counted independently: faces joined across edges that are not on the crack.
int components_across_uncracked_edges(const ParameterMesh& split) {
  std::vector<int> parent(static_cast<size_t>(split.num_faces()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)];
    return x;
  };
  std::map<std::pair<int, int>, int> face_of_edge;
  for (int f = 0; f < split.num_faces(); ++f) {
    const int begin = split.face_offsets[static_cast<size_t>(f)], end = split.face_offsets[static_cast<size_t>(f) + 1];
    for (int k = begin; k < end; ++k)
      if (!split.crack_edge[static_cast<size_t>(k)])
        face_of_edge[{split.face_vertices[static_cast<size_t>(k)], split.face_vertices[static_cast<size_t>(k + 1 < end ? k + 1 : begin)]}] = f;
  }
  for (const auto& [edge, f] : face_of_edge) {
    const auto twin = face_of_edge.find({edge.second, edge.first});
    if (twin != face_of_edge.end()) parent[static_cast<size_t>(find(f))] = find(twin->second);
  }
  int roots = 0;
  for (int f = 0; f < split.num_faces(); ++f) roots += find(f) == f;
  return roots;
}

TEST(CrackedTessellation, RandomCracksKeepEveryInvariant) {
  // Fixed-seed random polylines, many ending on grid lines, grid vertices or inside quads, crossing,
  // touching and overlapping.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> coordinate(-0.2, 1.2), step(-0.15, 0.15);
  for (int trial = 0; trial < 400; ++trial) {
    const int r = 1 + static_cast<int>(rng() % 7), s = 1 + static_cast<int>(rng() % 7);
    auto point = [&] {
      Vec2 p(coordinate(rng), coordinate(rng));
      const unsigned mode = rng() % 4;
      if (mode <= 1) p.x() = std::round(p.x() * r) / r;
      if (mode == 1) p.y() = std::round(p.y() * s) / s;
      return p;
    };
    std::vector<CrackSegment2> crack;
    Vec2 last = point();
    for (int k = 0, n = 2 + static_cast<int>(rng() % 10); k < n; ++k) {
      Vec2 next = rng() % 2 ? point() : Vec2(last + Vec2(step(rng), step(rng)));
      if (!crack.empty() && rng() % 6 == 0) next = crack[rng() % crack.size()].a;
      if (rng() % 4 == 0) last = point();
      crack.push_back({last, next});
      last = next;
    }
    const Split m = cut(crack, r, s);
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_valid(m, 1.0);
    EXPECT_EQ(count_components(m.separated), components_across_uncracked_edges(m.split));
    std::map<int, std::set<int>> faces_of;
    for (int f = 0; f < m.separated.num_faces(); ++f)
      for (int k = m.separated.face_offsets[static_cast<size_t>(f)]; k < m.separated.face_offsets[static_cast<size_t>(f) + 1]; ++k)
        if (m.separated.on_crack[static_cast<size_t>(m.separated.face_vertices[static_cast<size_t>(k)])])
          faces_of[m.separated.face_vertices[static_cast<size_t>(k)]].insert(f);
    for (const auto& [v, faces] : faces_of) {
      const Vec2& moved = m.separated.uv[static_cast<size_t>(v)];
      EXPECT_LE((moved - m.split.uv[static_cast<size_t>(m.separated.source_vertex[static_cast<size_t>(v)])]).norm(), 1e-5 + 1e-15);
      int winding = 0;
      for (int f : faces) winding += winding_number(m.split, f, moved);
      EXPECT_EQ(winding, 1);
    }
  }
}

TEST(CrackedTessellation, RejectsBadInput) {
  EXPECT_THROW(split_parameter_grid(kUnit, {}, grid(0, 3)), std::invalid_argument);
  EXPECT_THROW(split_parameter_grid(ParameterDomain{1.0, 1.0, 0.0, 1.0}, {}, grid(2, 2)), std::invalid_argument);
  const ParameterMesh m = split_parameter_grid(kUnit, {}, grid(2, 2));
  EXPECT_THROW(separate_crack_vertices(m, -1.0), std::invalid_argument);
  EXPECT_THROW(assemble_render_mesh(m, kUnit, {}, {}, "x"), std::invalid_argument);
}

TEST(CrackedTessellation, CountComponentsOfAPolyMesh) {
  PolyMesh mesh;
  mesh.positions.assign(7, Vec3::Zero());
  mesh.add_face({0, 1, 2});
  mesh.add_face({2, 3, 4});
  mesh.add_face({5, 6, 5});
  EXPECT_EQ(count_components(mesh), 2);
  EXPECT_EQ(count_components(PolyMesh{}), 0);
}

}  // namespace
}  // namespace shellfrac::render_mesh
