#pragma once
// Synthetic damage fields in a box of particles for the crack-surface and fragment tests.
#include <cmath>
#include <functional>
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle::testing {

// Particles on a lattice of spacing s filling [-L, L]^3 (half a spacing from the faces).
struct DamagedBox {
  double L, s;
  std::vector<Vec3> x;
  std::vector<double> c_his;
  DamagedBox(double half, double spacing, const std::function<bool(const Vec3&)>& damaged) : L(half), s(spacing) {
    const int n = static_cast<int>(std::lround(2 * half / spacing));
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Vec3 p(-half + spacing * (i + 0.5), -half + spacing * (j + 0.5), -half + spacing * (k + 0.5));
          x.push_back(p);
          c_his.push_back(damaged(p) ? 1.0 : 0.0);
        }
  }
};

// Distance from p to the half-plane through the z axis spanned by e_z and the unit direction u (xy).
inline double half_plane_distance(const Vec3& p, const Vec3& u) {
  const Vec3 q(p.x(), p.y(), 0);
  const double t = q.dot(u);
  return t >= 0 ? (q - t * u).norm() : q.norm();
}

// Area of a triangle soup clipped to the slab |x| <= L, |y| <= L (Sutherland-Hodgman per triangle).
inline double area_inside_xy(const TriMesh& m, double L) {
  double total = 0;
  for (const Tri& t : m.triangles) {
    std::vector<Vec3> poly{m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]};
    for (int axis = 0; axis < 2; ++axis)
      for (int sign = -1; sign <= 1; sign += 2) {
        std::vector<Vec3> out;
        for (size_t i = 0; i < poly.size(); ++i) {
          const Vec3 &a = poly[i], &b = poly[(i + 1) % poly.size()];
          const double da = L - sign * a[axis], db = L - sign * b[axis];  // >= 0 inside
          if (da >= 0) out.push_back(a);
          if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
        }
        poly.swap(out);
        if (poly.empty()) break;
      }
    for (size_t i = 1; i + 1 < poly.size(); ++i) total += 0.5 * (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).norm();
  }
  return total;
}

}  // namespace shellfrac::brittle::testing
