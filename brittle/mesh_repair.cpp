// Repair of an input mesh into a closed solid with CGAL Polygon Mesh Processing (solids[i].repair). Its
// own translation unit: CGAL is slow to compile.
#include "brittle/mesh_repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

namespace {

// Inexact constructions are enough: no step constructs a point, each only merges, splits or drops them.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

using Key = std::array<double, 3>;

Key key_of(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

// A triangle by its corner positions: the sorted corners, and whether the corner after the smallest is
// the larger of the other two (its orientation, comparable between meshes that share positions).
struct Oriented {
  std::array<Key, 3> corners;
  bool up;
};
Oriented oriented(const Key& a, const Key& b, const Key& c) {
  std::array<Key, 3> ring{a, b, c};
  const int first = static_cast<int>(std::min_element(ring.begin(), ring.end()) - ring.begin());
  const bool up = ring[(first + 2) % 3] < ring[(first + 1) % 3];
  std::sort(ring.begin(), ring.end());
  return {ring, up};
}

std::string counted(size_t n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

}  // namespace

bool MeshRepair::changed() const {
  return removed_vertices + removed_triangles + split_vertices + stitched_edges + reversed_triangles > 0;
}

std::string MeshRepair::describe() const {
  std::vector<std::string> parts;
  if (reversed_triangles > 0) parts.push_back(counted(reversed_triangles, "triangle reversed", "triangles reversed"));
  if (removed_triangles > 0)
    parts.push_back(counted(removed_triangles, "duplicate or degenerate triangle removed", "duplicate or degenerate triangles removed"));
  if (removed_vertices > 0)
    parts.push_back(counted(removed_vertices, "coincident or unused vertex removed", "coincident or unused vertices removed"));
  if (split_vertices > 0) parts.push_back(counted(split_vertices, "non-manifold vertex split", "non-manifold vertices split"));
  if (stitched_edges > 0) parts.push_back(counted(stitched_edges, "boundary edge pair stitched", "boundary edge pairs stitched"));
  if (parts.empty()) return "nothing changed";
  std::string out;
  for (size_t k = 0; k < parts.size(); ++k) out += (k == 0 ? "" : ", ") + parts[k];
  return out;
}

TriMesh repair_closed_solid(const TriMesh& in, const std::string& source, MeshRepair& changes) {
  changes = MeshRepair{};
  const MeshReport report = inspect_mesh(in);
  // Nothing to repair from: the refusal is require_closed_solid's.
  if (in.triangles.empty() || report.bad_indices > 0 || report.non_finite > 0) require_closed_solid(in, source);

  std::vector<Point> points;
  points.reserve(in.positions.size());
  for (const Vec3& p : in.positions) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(in.triangles.size());
  for (const Tri& t : in.triangles)
    polygons.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2])});

  PMP::repair_polygon_soup(points, polygons);
  changes.removed_vertices = in.positions.size() - points.size();
  changes.removed_triangles = in.triangles.size() - polygons.size();
  // Orienting may duplicate points where the soup cannot be one manifold (parts touching at a vertex
  // or along an edge); the check below refuses those, as the exact cutter welds them back.
  const size_t soup_points = points.size();
  PMP::orient_polygon_soup(points, polygons);
  changes.split_vertices = points.size() - soup_points;

  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  changes.stitched_edges = PMP::stitch_borders(mesh);
  const size_t faces = mesh.number_of_faces();
  PMP::remove_degenerate_faces(mesh);
  mesh.collect_garbage();
  changes.removed_triangles += faces - std::min(faces, static_cast<size_t>(mesh.number_of_faces()));
  // Each component outward, cavities inward; needs a closed surface (the check below names the holes).
  if (!mesh.is_empty() && CGAL::is_closed(mesh)) PMP::orient_to_bound_a_volume(mesh);

  TriMesh out;
  out.name = in.name;
  std::map<Mesh::Vertex_index, int> id;
  for (const auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    id[v] = static_cast<int>(out.positions.size());
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (const auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) t[static_cast<size_t>(k)] = id[v];
      ++k;
    }
    if (k == 3) out.triangles.emplace_back(t[0], t[1], t[2]);
  }

  // Reversals counted against the input's triangles at the same positions.
  std::map<std::array<Key, 3>, bool> input_up;
  for (const Tri& t : in.triangles) {
    const Oriented o = oriented(key_of(in.positions[t[0]]), key_of(in.positions[t[1]]), key_of(in.positions[t[2]]));
    input_up.emplace(o.corners, o.up);
  }
  for (const Tri& t : out.triangles) {
    const Oriented o = oriented(key_of(out.positions[t[0]]), key_of(out.positions[t[1]]), key_of(out.positions[t[2]]));
    const auto it = input_up.find(o.corners);
    if (it != input_up.end() && it->second != o.up) ++changes.reversed_triangles;
  }

  require_closed_solid(out, source + " (after repair: " + changes.describe() + ")");
  return out;
}

}  // namespace shellfrac::brittle
