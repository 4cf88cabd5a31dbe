// Measures of render and parameter meshes: area, connected pieces, a face's signed area.
#include "core/union_find.hpp"
#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/plane_geometry.hpp"

#include <Eigen/Geometry>

namespace shellfrac::render_mesh {

namespace {

// Pieces of a face list: vertices joined through shared faces, counted over the vertices faces use.
template <class FaceVertices>
int count_face_components(int num_vertices, const std::vector<int>& offsets, const FaceVertices& vertices) {
  core::UnionFind sets(static_cast<size_t>(num_vertices));
  std::vector<unsigned char> referenced(static_cast<size_t>(num_vertices), 0);
  for (size_t f = 0; f + 1 < offsets.size(); ++f)
    for (int k = offsets[f]; k < offsets[f + 1]; ++k) {
      const int v = vertices[static_cast<size_t>(k)];
      referenced[static_cast<size_t>(v)] = 1;
      sets.unite(static_cast<size_t>(v), static_cast<size_t>(vertices[static_cast<size_t>(offsets[f])]));
    }
  int components = 0;
  for (int v = 0; v < num_vertices; ++v)
    if (referenced[static_cast<size_t>(v)] && sets.find(static_cast<size_t>(v)) == static_cast<size_t>(v)) ++components;
  return components;
}

}  // namespace

double surface_area(const PolyMesh& m) {
  double area = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const auto b = static_cast<size_t>(m.face_offsets[static_cast<size_t>(f)]);
    const auto e = static_cast<size_t>(m.face_offsets[static_cast<size_t>(f) + 1]);
    const Eigen::Vector3d& o = m.positions[static_cast<size_t>(m.face_vertices[b])];
    Eigen::Vector3d twice = Eigen::Vector3d::Zero();
    for (size_t k = b + 1; k + 1 < e; ++k)
      twice += (m.positions[static_cast<size_t>(m.face_vertices[k])] - o)
                   .cross(m.positions[static_cast<size_t>(m.face_vertices[k + 1])] - o);
    area += 0.5 * twice.norm();
  }
  return area;
}

int count_components(const PolyMesh& mesh) {
  return count_face_components(mesh.num_vertices(), mesh.face_offsets, mesh.face_vertices);
}

int count_components(const ParameterMesh& mesh) {
  return count_face_components(mesh.num_vertices(), mesh.face_offsets, mesh.face_vertices);
}

double signed_area(const ParameterMesh& mesh, int face) {
  const int begin = mesh.face_offsets[static_cast<size_t>(face)], end = mesh.face_offsets[static_cast<size_t>(face) + 1];
  double twice = 0.0;
  for (int k = begin; k < end; ++k) {
    const Vec2& a = mesh.uv[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])];
    const Vec2& b = mesh.uv[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k + 1 < end ? k + 1 : begin)])];
    twice += detail::cross2(a, b);
  }
  return 0.5 * twice;
}

}  // namespace shellfrac::render_mesh
