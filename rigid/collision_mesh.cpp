#include "rigid/collision_mesh.hpp"

#include <LinearMath/btConvexHullComputer.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace shellfrac::rigid {

namespace {

// Vertices split at attribute seams are one vertex for the collision shape.
brittle::TriMesh weld(const brittle::TriMesh& mesh) {
  brittle::TriMesh out;
  out.name = mesh.name;
  std::map<std::array<double, 3>, int> index;
  std::vector<int> remap(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const brittle::Vec3& p = mesh.positions[i];
    const auto [it, inserted] = index.try_emplace({p.x(), p.y(), p.z()}, static_cast<int>(out.positions.size()));
    if (inserted) out.positions.push_back(p);
    remap[i] = it->second;
  }
  for (const brittle::Tri& t : mesh.triangles) {
    const brittle::Tri w(remap[t[0]], remap[t[1]], remap[t[2]]);
    if (w[0] != w[1] && w[1] != w[2] && w[0] != w[2]) out.triangles.push_back(w);
  }
  return out;
}

// Drops vertices no triangle uses.
void compact(brittle::TriMesh& mesh) {
  std::vector<int> remap(mesh.positions.size(), -1);
  std::vector<brittle::Vec3> kept;
  for (brittle::Tri& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      int& r = remap[t[k]];
      if (r < 0) {
        r = static_cast<int>(kept.size());
        kept.push_back(mesh.positions[t[k]]);
      }
      t[k] = r;
    }
  mesh.positions = std::move(kept);
}

}  // namespace

DecimatedMesh decimate(const brittle::TriMesh& mesh, size_t max_triangles) {
  DecimatedMesh out;
  out.mesh = weld(mesh);
  if (out.mesh.triangles.size() <= max_triangles || max_triangles < 4) return out;
  // meshoptimizer reads float positions; the result indexes the double positions we keep.
  std::vector<float> xyz;
  xyz.reserve(3 * out.mesh.positions.size());
  for (const brittle::Vec3& p : out.mesh.positions)
    for (int k = 0; k < 3; ++k) xyz.push_back(static_cast<float>(p[k]));
  std::vector<unsigned> indices;
  indices.reserve(3 * out.mesh.triangles.size());
  for (const brittle::Tri& t : out.mesh.triangles)
    for (int k = 0; k < 3; ++k) indices.push_back(static_cast<unsigned>(t[k]));
  std::vector<unsigned> simplified(indices.size());
  float error = 0;
  // target_error 1: the face budget, not an error bound, decides where collapsing stops.
  const size_t n = meshopt_simplify(simplified.data(), indices.data(), indices.size(), xyz.data(),
                                    out.mesh.positions.size(), 3 * sizeof(float), 3 * max_triangles, 1.0f, 0, &error);
  out.mesh.triangles.clear();
  for (size_t i = 0; i + 2 < n; i += 3)
    out.mesh.triangles.emplace_back(static_cast<int>(simplified[i]), static_cast<int>(simplified[i + 1]),
                                    static_cast<int>(simplified[i + 2]));
  compact(out.mesh);
  out.relative_error = error;
  return out;
}

double hull_volume_ratio(const brittle::TriMesh& mesh) {
  const double volume = brittle::inspect_mesh(mesh).volume;
  if (!(volume > 0) || mesh.positions.size() < 4) return INFINITY;
  btConvexHullComputer hull;
  hull.compute(mesh.positions.data()->data(), static_cast<int>(sizeof(brittle::Vec3)), static_cast<int>(mesh.positions.size()),
               0, 0);
  // Hull volume as a fan of tetrahedra from the first hull vertex over every (planar, convex) face.
  if (hull.vertices.size() < 4) return INFINITY;
  const btVector3 o = hull.vertices[0];
  double hull_volume = 0;
  for (int f = 0; f < hull.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
    const btVector3 a = hull.vertices[first->getSourceVertex()];
    const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace();
    for (; e->getTargetVertex() != first->getSourceVertex(); e = e->getNextEdgeOfFace()) {
      const btVector3 b = hull.vertices[e->getSourceVertex()], c = hull.vertices[e->getTargetVertex()];
      hull_volume += (a - o).dot((b - o).cross(c - o)) / 6.0;
    }
  }
  return std::abs(hull_volume) / volume;
}

}  // namespace shellfrac::rigid
