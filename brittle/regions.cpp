#include "brittle/regions.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

namespace shellfrac::brittle {

Regions find_regions(const VoronoiDiagram& d, const std::vector<char>& crack_face) {
  Regions r;
  r.cell_region.assign(d.num_cells(), -1);
  for (size_t start = 0; start < d.num_cells(); ++start) {
    if (r.cell_region[start] >= 0) continue;
    const int id = r.count++;
    std::deque<int> queue{static_cast<int>(start)};
    r.cell_region[start] = id;
    flood_cells(d, crack_face, r.cell_region, queue, [](int) { return true; });
  }
  return r;
}

TriMesh region_boundary(const VoronoiDiagram& d, const Regions& r, int region) {
  TriMesh m;
  m.name = "region_" + std::to_string(region);
  std::vector<int> remap(d.vertices.size(), -1);
  auto vid = [&](int v) {
    int& id = remap[static_cast<size_t>(v)];
    if (id < 0) {
      id = static_cast<int>(m.positions.size());
      m.positions.push_back(d.vertices[static_cast<size_t>(v)]);
    }
    return id;
  };
  for (const VoronoiFace& f : d.faces) {
    const bool in_a = r.cell_region[static_cast<size_t>(f.cell_a)] == region;
    const bool in_b = !f.wall() && r.cell_region[static_cast<size_t>(f.cell_b)] == region;
    if (in_a == in_b) continue;
    // Normals from a to b: outward for a, reversed for b. The triangulation is the face's own, so both
    // regions share identical triangles (the centre of a bent face is computed from the same vertices).
    int centre = -1;
    if (f.bent) {
      centre = static_cast<int>(m.positions.size());
      m.positions.push_back(face_centre(d.vertices, f));
    }
    for_face_triangles(f, [&](int a, int b, int c) {
      const int ia = a < 0 ? centre : vid(a), ib = vid(b), ic = vid(c);
      if (in_b) m.triangles.emplace_back(ia, ic, ib);
      else m.triangles.emplace_back(ia, ib, ic);
    });
  }
  return m;
}

std::vector<size_t> points_per_region(const VoronoiDiagram& d, const Regions& r, const std::vector<Vec3>& points) {
  std::vector<size_t> count(static_cast<size_t>(r.count), 0);
  if (d.sites.empty()) return count;
  const SiteLocator locate(d);
  for (const Vec3& p : points) {
    const int c = locate.cell_of(p);
    if (c >= 0) ++count[static_cast<size_t>(r.cell_region[static_cast<size_t>(c)])];
  }
  return count;
}

}  // namespace shellfrac::brittle
