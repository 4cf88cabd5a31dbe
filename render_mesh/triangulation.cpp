#include "render_mesh/triangulation.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numeric>

#include "render_mesh/plane_geometry.hpp"

namespace shellfrac::render_mesh {

using detail::cross2;

namespace {

// Above this many corners the best-shaped ear is no longer searched for (O(n^3)); the first valid ear
// after the last cut is taken instead (O(n^2)), which is still deterministic.
constexpr size_t kShapeSearchCorners = 48;

// Closed point-in-triangle test for a triangle wound with sign s (+1 counter-clockwise).
bool in_closed_triangle(const Vec2& q, const Vec2& a, const Vec2& b, const Vec2& c, double s) {
  return s * cross2(b - a, q - a) >= 0.0 && s * cross2(c - b, q - b) >= 0.0 && s * cross2(a - c, q - c) >= 0.0;
}

double shape_quality(const Vec2& a, const Vec2& b, const Vec2& c, double twice_area) {
  const double sides = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return sides > 0.0 ? 2.0 * std::sqrt(3.0) * twice_area / sides : 0.0;  // 1 for an equilateral triangle
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec2>& p) {
  const size_t n = p.size();
  std::vector<std::array<int, 3>> out;
  if (n < 3) return out;
  out.reserve(n - 2);
  double twice = 0.0;
  for (size_t k = 0; k < n; ++k) twice += cross2(p[k], p[(k + 1) % n]);
  const double s = twice >= 0.0 ? 1.0 : -1.0;

  std::vector<int> ring(n);
  std::iota(ring.begin(), ring.end(), 0);
  size_t start = 0;  // where the scan for the first valid ear begins (large polygons)
  while (ring.size() > 3) {
    const size_t m = ring.size();
    auto corner = [&](size_t i) { return ring[(i + m) % m]; };
    auto is_ear = [&](size_t i, double& twice_area) {
      const int a = corner(i + m - 1), b = corner(i), c = corner(i + 1);
      twice_area = s * cross2(p[b] - p[a], p[c] - p[b]);
      if (!(twice_area > 0.0)) return false;
      for (size_t k = 0; k < m; ++k) {
        const int r = ring[k];
        if (r == a || r == b || r == c) continue;
        // A corner repeated at the same point (a keyhole) touches the ear only at its own corner.
        if (p[r] == p[a] || p[r] == p[b] || p[r] == p[c]) continue;
        if (in_closed_triangle(p[r], p[a], p[b], p[c], s)) return false;
      }
      return true;
    };
    size_t chosen = m;
    if (m <= kShapeSearchCorners) {
      double best = -1.0;
      for (size_t i = 0; i < m; ++i) {
        double twice_area = 0.0;
        if (!is_ear(i, twice_area)) continue;
        const double q = shape_quality(p[corner(i + m - 1)], p[corner(i)], p[corner(i + 1)], twice_area);
        if (q > best + 1e-12) best = q, chosen = i;
      }
    } else {
      for (size_t k = 0; k < m && chosen == m; ++k) {
        double twice_area = 0.0;
        if (is_ear((start + k) % m, twice_area)) chosen = (start + k) % m;
      }
    }
    if (chosen == m) {
      // No valid ear (rounding on a degenerate polygon): cut the most convex corner.
      double most = -std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < m; ++i) {
        const int a = corner(i + m - 1), b = corner(i), c = corner(i + 1);
        const double t = s * cross2(p[b] - p[a], p[c] - p[b]);
        if (t > most) most = t, chosen = i;
      }
    }
    out.push_back({corner(chosen + m - 1), corner(chosen), corner(chosen + 1)});
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(chosen));
    start = chosen % ring.size();
  }
  out.push_back({ring[0], ring[1], ring[2]});
  return out;
}

std::vector<Vec2> face_plane_corners(const PolyMesh& mesh, int face) {
  const auto b = static_cast<size_t>(mesh.face_offsets[static_cast<size_t>(face)]);
  const auto e = static_cast<size_t>(mesh.face_offsets[static_cast<size_t>(face) + 1]);
  std::vector<Vec2> corners;
  corners.reserve(e - b);
  if (mesh.uvs.size() == mesh.positions.size()) {
    for (size_t k = b; k < e; ++k) corners.push_back(mesh.uvs[static_cast<size_t>(mesh.face_vertices[k])]);
    return corners;
  }
  Vec3 normal = Vec3::Zero();  // Newell: twice the vector area
  for (size_t k = b; k < e; ++k) {
    const Vec3& x = mesh.positions[static_cast<size_t>(mesh.face_vertices[k])];
    const Vec3& y = mesh.positions[static_cast<size_t>(mesh.face_vertices[k + 1 < e ? k + 1 : b])];
    normal += x.cross(y);
  }
  if (!(normal.norm() > 0.0)) normal = Vec3::UnitZ();
  normal.normalize();
  // Any orthonormal pair (t1, t2) with t1 x t2 = normal keeps the polygon's orientation.
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 t1 = normal.cross(helper).normalized();
  const Vec3 t2 = normal.cross(t1);
  for (size_t k = b; k < e; ++k) {
    const Vec3& x = mesh.positions[static_cast<size_t>(mesh.face_vertices[k])];
    corners.emplace_back(x.dot(t1), x.dot(t2));
  }
  return corners;
}

std::vector<std::array<int, 3>> face_triangles(const PolyMesh& mesh, int face) {
  const int b = mesh.face_offsets[static_cast<size_t>(face)];
  const int e = mesh.face_offsets[static_cast<size_t>(face) + 1];
  std::vector<std::array<int, 3>> out;
  if (e - b < 3) return out;
  auto vertex = [&](int corner) { return mesh.face_vertices[static_cast<size_t>(b + corner)]; };
  if (e - b == 3) return {{vertex(0), vertex(1), vertex(2)}};
  for (const auto& t : triangulate_polygon(face_plane_corners(mesh, face)))
    out.push_back({vertex(t[0]), vertex(t[1]), vertex(t[2])});
  return out;
}

Triangulation triangulate(const PolyMesh& mesh) {
  Triangulation out;
  out.mesh.name = mesh.name;
  out.mesh.positions = mesh.positions;
  out.mesh.normals = mesh.normals;
  out.mesh.uvs = mesh.uvs;
  out.mesh.face_vertices.reserve(mesh.face_vertices.size() * 3 / 2);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int b = mesh.face_offsets[static_cast<size_t>(f)], e = mesh.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b <= 3) {
      out.mesh.face_vertices.insert(out.mesh.face_vertices.end(), mesh.face_vertices.begin() + b,
                                    mesh.face_vertices.begin() + e);
      out.mesh.face_offsets.push_back(static_cast<int>(out.mesh.face_vertices.size()));
      out.source_face.push_back(f);
      continue;
    }
    for (const auto& t : face_triangles(mesh, f)) {
      out.mesh.add_face({t[0], t[1], t[2]});
      out.source_face.push_back(f);
    }
  }
  return out;
}

}  // namespace shellfrac::render_mesh
