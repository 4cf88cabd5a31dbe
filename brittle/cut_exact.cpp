// Exact fragment cutting with CGAL Polygon Mesh Processing corefinement (thesis Fig. 3.9d). One of the
// two translation units that include CGAL (with mesh_repair.cpp): it is slow to compile.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include <map>
#include <sstream>
#include <tuple>

#include "brittle/errors.hpp"
#include "brittle/fragments.hpp"

namespace shellfrac::brittle {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A closed triangle mesh as a CGAL surface mesh, vertices welded by position. Returns false when a face
// cannot be added (non-manifold or inconsistently oriented).
bool to_cgal(const TriMesh& m, Mesh& out) {
  out.clear();
  std::map<std::tuple<double, double, double>, Mesh::Vertex_index> weld;
  std::vector<Mesh::Vertex_index> v(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3& p = m.positions[i];
    auto it = weld.find({p.x(), p.y(), p.z()});
    if (it == weld.end()) it = weld.emplace(std::make_tuple(p.x(), p.y(), p.z()), out.add_vertex(Point(p.x(), p.y(), p.z()))).first;
    v[i] = it->second;
  }
  for (const Tri& t : m.triangles) {
    const auto a = v[static_cast<size_t>(t[0])], b = v[static_cast<size_t>(t[1])], c = v[static_cast<size_t>(t[2])];
    if (a == b || b == c || a == c) continue;
    if (out.add_face(a, b, c) == Mesh::null_face()) return false;
  }
  return true;
}

TriMesh from_cgal(const Mesh& m) {
  TriMesh out;
  std::map<Mesh::Vertex_index, int> id;
  for (const auto v : m.vertices()) {
    const Point& p = m.point(v);
    id[v] = static_cast<int>(out.positions.size());
    out.positions.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  for (const auto f : m.faces()) {
    Tri t;
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (k < 3) t[k] = id[v];
      ++k;
    }
    if (k == 3) out.triangles.push_back(t);
  }
  return out;
}

}  // namespace

bool exact_cutter_accepts(const TriMesh& mesh) {
  Mesh m;
  return to_cgal(mesh, m);
}

FragmentSet cut_fragments_exact(const TriMesh& domain, const VoronoiDiagram& diagram, const Regions& regions,
                                const FragmentOptions& o, const std::string& source) {
  FragmentSet set;
  set.cutter = Cutter::Exact;
  set.input_volume = mass_properties(domain, 1.0).volume;
  Mesh domain_mesh;
  if (!to_cgal(domain, domain_mesh))
    throw InputError(source + ": mesh '" + domain.name + "' has non-manifold or inconsistently oriented faces; the exact cutter needs a manifold surface");
  Vec3 lo, hi;
  bounding_box(domain, lo, hi);
  const double tol = 1e-9 * (hi - lo).norm();
  for (int r = 0; r < regions.count; ++r) {
    const TriMesh boundary = region_boundary(diagram, regions, r);
    Mesh region_mesh, a = domain_mesh, result;
    if (!to_cgal(boundary, region_mesh))
      throw NumericalError("exact cutter: the boundary of Voronoi region " + std::to_string(r) + " is not a manifold surface");
    bool ok = false;
    try {
      ok = PMP::corefine_and_compute_intersection(a, region_mesh, result);
    } catch (const std::exception& e) {
      throw NumericalError("exact cutter: corefinement of Voronoi region " + std::to_string(r) + " with '" + domain.name +
                           "' failed: " + e.what());
    }
    if (!ok)
      throw NumericalError("exact cutter: the intersection of Voronoi region " + std::to_string(r) + " with '" + domain.name +
                           "' is not a closed solid (self-intersecting input?)");
    if (result.number_of_faces() == 0) continue;
    add_fragments(set, from_cgal(result), r, domain, o, tol);
  }
  return set;
}

}  // namespace shellfrac::brittle
