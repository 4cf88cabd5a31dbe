#include "render_mesh/triangulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "render_mesh/cracked_tessellation.hpp"

namespace shellfrac::render_mesh {
namespace {

const double kPi = std::acos(-1.0);

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double shoelace(const std::vector<Vec2>& p) {
  double twice = 0.0;
  for (size_t k = 0; k < p.size(); ++k) twice += cross(p[k], p[(k + 1) % p.size()]);
  return 0.5 * twice;
}

double signed_triangle_area(const std::vector<Vec2>& p, const std::array<int, 3>& t) {
  return 0.5 * cross(p[static_cast<size_t>(t[1])] - p[static_cast<size_t>(t[0])], p[static_cast<size_t>(t[2])] - p[static_cast<size_t>(t[0])]);
}

// Even-odd point-in-polygon test (independent of the triangulation).
bool inside_polygon(const std::vector<Vec2>& p, const Vec2& q) {
  bool inside = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
    if ((p[i].y() > q.y()) != (p[j].y() > q.y()) &&
        q.x() < (p[j].x() - p[i].x()) * (q.y() - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x())
      inside = !inside;
  return inside;
}

bool strictly_inside_triangle(const std::vector<Vec2>& p, const std::array<int, 3>& t, const Vec2& q) {
  const Vec2 &a = p[static_cast<size_t>(t[0])], &b = p[static_cast<size_t>(t[1])], &c = p[static_cast<size_t>(t[2])];
  const double d1 = cross(b - a, q - a), d2 = cross(c - b, q - b), d3 = cross(a - c, q - c);
  return (d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0);
}

// "Covers exactly": on a fine sample grid (offsets irrational so no sample lies on an edge), every point
// inside the polygon lies in exactly one triangle and every point outside in none. Returns the number
// of samples that break this.
int coverage_errors(const std::vector<Vec2>& p, const std::vector<std::array<int, 3>>& triangles, int samples = 400) {
  Vec2 lo = p[0], hi = p[0];
  for (const Vec2& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  int errors = 0;
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < samples; ++j) {
      const Vec2 q(lo.x() + (hi.x() - lo.x()) * (i + 0.5 + 0.1 * std::sqrt(2.0)) / samples,
                   lo.y() + (hi.y() - lo.y()) * (j + 0.5 + 0.1 * std::sqrt(3.0)) / samples);
      int covering = 0;
      for (const auto& t : triangles) covering += strictly_inside_triangle(p, t, q) ? 1 : 0;
      errors += covering != (inside_polygon(p, q) ? 1 : 0) ? 1 : 0;
    }
  return errors;
}

void expect_exact_cover(const std::vector<Vec2>& p, const std::vector<std::array<int, 3>>& triangles) {
  ASSERT_EQ(triangles.size(), p.size() - 2);
  const double area = shoelace(p);
  double sum = 0.0;
  for (const auto& t : triangles) {
    const double a = signed_triangle_area(p, t);
    EXPECT_GT(a * (area > 0 ? 1 : -1), 0.0) << "a triangle winds against the polygon or is flat";
    sum += a;
  }
  EXPECT_NEAR(sum, area, 1e-14 * std::abs(area));
  EXPECT_EQ(coverage_errors(p, triangles), 0);
}

// A unit square with a slit of width 2w from the middle of its right side to its centre: the polygon
// the cracked tessellation makes around a crack tip (thesis Fig. 4.16), strongly non-convex.
std::vector<Vec2> slit_square(double w) {
  return {{0, 0}, {1, 0}, {1, 0.5 - w}, {0.5, 0.5}, {1, 0.5 + w}, {1, 1}, {0, 1}};
}

TEST(Triangulation, SlitSquareIsCoveredExactlyWhereAFanFails) {
  for (const double w : {0.1, 1e-3, 1e-5}) {
    SCOPED_TRACE("slit half width " + std::to_string(w));
    const auto p = slit_square(w);
    expect_exact_cover(p, triangulate_polygon(p));
    EXPECT_NEAR(shoelace(p), 1.0 - 0.5 * w, 1e-15);  // square minus the slit triangle (base 2w, height 0.5)
  }
  // The fan from corner 0 is wrong on this polygon: it covers the slit and folds a triangle over.
  const auto p = slit_square(0.1);
  std::vector<std::array<int, 3>> fan;
  for (int k = 1; k + 1 < static_cast<int>(p.size()); ++k) fan.push_back({0, k, k + 1});
  EXPECT_GT(coverage_errors(p, fan), 0);
}

TEST(Triangulation, StarCombAndClockwisePolygons) {
  std::vector<Vec2> star;  // 9 spikes: every other corner reflex
  for (int k = 0; k < 18; ++k) {
    const double r = k % 2 ? 0.3 : 1.0, a = 2 * kPi * k / 18 + 0.05;
    star.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  expect_exact_cover(star, triangulate_polygon(star));
  // A comb: five teeth on a bar; not star-shaped, so no single fan centre exists.
  const std::vector<Vec2> comb{{0, 0}, {9, 0}, {9, 3}, {8, 3}, {8, 1}, {7, 1}, {7, 3}, {6, 3}, {6, 1}, {5, 1},
                               {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  expect_exact_cover(comb, triangulate_polygon(comb));
  // Clockwise input: triangles wind clockwise too, and still cover exactly.
  std::vector<Vec2> reversed(star.rbegin(), star.rend());
  const auto triangles = triangulate_polygon(reversed);
  expect_exact_cover(reversed, triangles);
  EXPECT_LT(signed_triangle_area(reversed, triangles.front()), 0.0);
}

TEST(Triangulation, CollinearCornersGiveNoFlatTriangles) {
  // A quad whose sides are split by extra corners, as where cracked quads share their edges.
  const std::vector<Vec2> p{{0, 0}, {0.25, 0}, {0.5, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.7}};
  const auto triangles = triangulate_polygon(p);
  expect_exact_cover(p, triangles);
  for (const auto& t : triangles) EXPECT_GT(signed_triangle_area(p, t), 0.05) << t[0] << " " << t[1] << " " << t[2];
  // Triangle and degenerate input.
  EXPECT_EQ(triangulate_polygon({{0, 0}, {1, 0}, {0, 1}}).size(), 1u);
  EXPECT_TRUE(triangulate_polygon({{0, 0}, {1, 0}}).empty());
  EXPECT_EQ(triangulate_polygon({{0, 0}, {1, 0}, {2, 0}, {3, 0}}).size(), 2u);  // all collinear: still n - 2
}

TEST(Triangulation, MeshKeepsVerticesAndIsFrameIndependent) {
  // A cracked 6 x 5 tessellation with a tip inside a quad, a junction and a floating loop.
  CrackedTessellationSettings settings;
  settings.resolution_u = 6;
  settings.resolution_v = 5;
  const ParameterDomain domain;
  std::vector<CrackSegment2> crack{{{0.0, 0.43}, {0.47, 0.52}}, {{0.47, 0.52}, {0.71, 0.83}}, {{0.47, 0.52}, {0.66, 0.31}}};
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * kPi * k / 8, b = 2 * kPi * (k + 1) / 8;
    crack.push_back({{0.2 + 0.05 * std::cos(a), 0.8 + 0.05 * std::sin(a)}, {0.2 + 0.05 * std::cos(b), 0.8 + 0.05 * std::sin(b)}});
  }
  const ParameterMesh separated = separate_crack_vertices(split_parameter_grid(domain, crack, settings), 1e-5);
  auto frame = [&](double t) {  // a curved, time-dependent placement of the same tessellation
    return cracked_tessellation(separated, domain, [t](const Vec2& uv) {
      return Vec3(uv.x() + 0.1 * t * uv.y(), uv.y(), std::sin(3 * uv.x() + t) * 0.2);
    }, "sheet");
  };
  const PolyMesh a = frame(0.0), b = frame(1.7);
  const Triangulation ta = triangulate(a), tb = triangulate(b);
  EXPECT_EQ(ta.mesh.face_vertices, tb.mesh.face_vertices);  // decided in the parameter plane only
  EXPECT_EQ(ta.mesh.positions, a.positions);
  EXPECT_EQ(ta.mesh.uvs, a.uvs);
  EXPECT_EQ(ta.mesh.normals, a.normals);
  size_t expected = 0;
  for (int f = 0; f < a.num_faces(); ++f) expected += static_cast<size_t>(a.face_offsets[f + 1] - a.face_offsets[f] - 2);
  ASSERT_EQ(static_cast<size_t>(ta.mesh.num_faces()), expected);
  ASSERT_EQ(ta.source_face.size(), expected);
  // Every triangle is counter-clockwise in the parameter plane and the areas add up per source face.
  std::vector<double> area(static_cast<size_t>(a.num_faces()), 0.0);
  double smallest = 1e300;
  for (int f = 0; f < ta.mesh.num_faces(); ++f) {
    const int* v = &ta.mesh.face_vertices[static_cast<size_t>(ta.mesh.face_offsets[f])];
    const double t = 0.5 * cross(a.uvs[v[1]] - a.uvs[v[0]], a.uvs[v[2]] - a.uvs[v[0]]);
    smallest = std::min(smallest, t);
    area[static_cast<size_t>(ta.source_face[static_cast<size_t>(f)])] += t;
  }
  EXPECT_GT(smallest, 0.0);
  for (int f = 0; f < a.num_faces(); ++f) EXPECT_NEAR(area[static_cast<size_t>(f)], signed_area(separated, f), 1e-15);
}

TEST(Triangulation, RandomCrackedTessellationsGiveOnlyPositiveTriangles) {
  // The polygons of random cracks (tips, junctions, crossings, slits; fixed seed) are simple in the
  // parameter plane, so ear clipping must give positive triangles that add up to each polygon.
  std::mt19937 rng(777);
  std::uniform_real_distribution<double> coordinate(-0.1, 1.1), step(-0.2, 0.2);
  size_t triangles = 0;
  double worst_area_error = 0.0, smallest = 1e300;
  for (int trial = 0; trial < 200; ++trial) {
    CrackedTessellationSettings settings;
    settings.resolution_u = 1 + static_cast<int>(rng() % 6);
    settings.resolution_v = 1 + static_cast<int>(rng() % 6);
    std::vector<CrackSegment2> crack;
    Vec2 last(coordinate(rng), coordinate(rng));
    for (int k = 0, n = 2 + static_cast<int>(rng() % 8); k < n; ++k) {
      const Vec2 next = rng() % 2 ? Vec2(coordinate(rng), coordinate(rng)) : Vec2(last + Vec2(step(rng), step(rng)));
      crack.push_back({last, next});
      last = rng() % 3 ? next : Vec2(coordinate(rng), coordinate(rng));
    }
    const ParameterMesh m = separate_crack_vertices(split_parameter_grid({}, crack, settings), 1e-5);
    for (int f = 0; f < m.num_faces(); ++f) {
      std::vector<Vec2> corners;
      for (int k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) corners.push_back(m.uv[static_cast<size_t>(m.face_vertices[k])]);
      double sum = 0.0;
      for (const auto& t : triangulate_polygon(corners)) {
        const double a = signed_triangle_area(corners, t);
        smallest = std::min(smallest, a);
        sum += a;
        ++triangles;
      }
      worst_area_error = std::max(worst_area_error, std::abs(sum - signed_area(m, f)));
    }
  }
  EXPECT_GT(triangles, 5000u);
  EXPECT_GT(smallest, 0.0);
  EXPECT_LE(worst_area_error, 1e-15);
}

}  // namespace
}  // namespace shellfrac::render_mesh
