#include "brittle/primitives.hpp"

#include <cmath>

namespace shellfrac::brittle {

namespace {

constexpr double kPi = 3.14159265358979323846;

int add_vertex(TriMesh& m, const Vec3& p, const Vec3& n, const Vec2& uv) {
  m.positions.push_back(p);
  m.normals.push_back(n);
  m.uvs.push_back(uv);
  return static_cast<int>(m.positions.size()) - 1;
}

// A (rows+1) x (cols+1) vertex grid from f(u, v) -> (position, normal), u, v in [0, 1], as triangles;
// flip reverses the winding.
template <class F>
void add_grid(TriMesh& m, int cols, int rows, F&& f, bool flip = false, bool wrap_u = false, bool wrap_v = false) {
  const int first = static_cast<int>(m.positions.size());
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= cols; ++c) {
      // Positions of the closing column/row repeat the first one exactly (cos(2 pi) != cos(0) in
      // floating point), so that seams weld; the UVs still run to 1.
      const double u = static_cast<double>(c) / cols, v = static_cast<double>(r) / rows;
      const double pu = wrap_u && c == cols ? 0.0 : u, pv = wrap_v && r == rows ? 0.0 : v;
      Vec3 p, n;
      f(pu, pv, p, n);
      add_vertex(m, p, n, Vec2(u, v));
    }
  auto id = [&](int c, int r) { return first + r * (cols + 1) + c; };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      Tri t1(id(c, r), id(c + 1, r), id(c + 1, r + 1)), t2(id(c, r), id(c + 1, r + 1), id(c, r + 1));
      if (flip) {
        std::swap(t1[1], t1[2]);
        std::swap(t2[1], t2[2]);
      }
      m.triangles.push_back(t1);
      m.triangles.push_back(t2);
    }
}

}  // namespace

TriMesh box_mesh(const Vec3& c, const Vec3& h, int subdivisions) {
  TriMesh m;
  m.name = "box";
  const int n = std::max(1, subdivisions);
  // Each face: outward normal along axis a (sign s), tangents b and c chosen so that b x c = s e_a.
  for (int a = 0; a < 3; ++a)
    for (int s = -1; s <= 1; s += 2) {
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      add_grid(m, n, n, [&](double u, double v, Vec3& p, Vec3& nn) {
        p = c;
        p[a] += s * h[a];
        p[b] += (2 * u - 1) * h[b];
        p[d] += (2 * v - 1) * h[d];
        nn = Vec3::Zero();
        nn[a] = s;
      }, s < 0);
    }
  return m;
}

TriMesh sphere_mesh(const Vec3& c, double radius, int segments, int rings) {
  TriMesh m;
  m.name = "sphere";
  // Latitude-longitude grid; the pole rows collapse onto one point each (their zero-area triangles are
  // dropped below).
  add_grid(m, segments, rings, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u, theta = kPi * v;
    n = Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta));
    if (v == 0.0 || v == 1.0) n = Vec3(0, 0, v == 0.0 ? -1.0 : 1.0);
    p = c + radius * n;
  }, false, true);
  std::vector<Tri> kept;
  for (const Tri& t : m.triangles) {
    const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &d = m.positions[t[2]];
    if (a == b || b == d || a == d) continue;
    kept.push_back(t);
  }
  m.triangles = kept;
  return m;
}

TriMesh cylinder_mesh(const Vec3& c, double radius, double height, int segments) {
  TriMesh m;
  m.name = "cylinder";
  add_grid(m, segments, 1, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u;
    n = Vec3(std::cos(phi), std::sin(phi), 0);
    p = c + radius * n + Vec3(0, 0, (v - 0.5) * height);
  }, false, true);
  for (int s = -1; s <= 1; s += 2) {  // caps: a centre vertex and a ring
    const Vec3 n(0, 0, s);
    const int centre = add_vertex(m, c + Vec3(0, 0, 0.5 * s * height), n, Vec2(0.5, 0.5));
    const int first = static_cast<int>(m.positions.size());
    for (int k = 0; k <= segments; ++k) {
      const double phi = 2 * kPi * (static_cast<double>(k % segments) / segments);  // as the side grid, bit for bit
      add_vertex(m, c + Vec3(radius * std::cos(phi), radius * std::sin(phi), 0.5 * s * height), n,
                 Vec2(0.5 + 0.5 * std::cos(phi), 0.5 + 0.5 * std::sin(phi)));
    }
    for (int k = 0; k < segments; ++k)
      m.triangles.push_back(s > 0 ? Tri(centre, first + k, first + k + 1) : Tri(centre, first + k + 1, first + k));
  }
  return m;
}

TriMesh torus_mesh(const Vec3& c, double R, double r, int segments, int tube_segments) {
  TriMesh m;
  m.name = "torus";
  add_grid(m, segments, tube_segments, [&](double u, double v, Vec3& p, Vec3& n) {
    const double phi = 2 * kPi * u, theta = 2 * kPi * v;
    const Vec3 radial(std::cos(phi), std::sin(phi), 0);
    n = std::cos(theta) * radial + std::sin(theta) * Vec3::UnitZ();
    p = c + R * radial + r * n;
  }, false, true, true);
  return m;
}

}  // namespace shellfrac::brittle
