#include "render_mesh/surface_tessellation.hpp"

#include <stdexcept>

namespace shellfrac::render_mesh {

PolyMesh tessellate(const nurbs::NurbsSurface& surface, int resolution_u, int resolution_v,
                    const std::string& name) {
  if (resolution_u < 1 || resolution_v < 1)
    throw std::invalid_argument("render resolution must be at least 1 x 1");
  PolyMesh mesh;
  mesh.name = name;
  const int nu = resolution_u + 1, nv = resolution_v + 1;
  mesh.positions.reserve(static_cast<size_t>(nu * nv));
  mesh.normals.reserve(static_cast<size_t>(nu * nv));
  mesh.uvs.reserve(static_cast<size_t>(nu * nv));
  const auto& ku = surface.knots_u();
  const auto& kv = surface.knots_v();
  for (int j = 0; j < nv; ++j) {
    const double t = static_cast<double>(j) / resolution_v;
    const double v = kv.domain_begin() + t * (kv.domain_end() - kv.domain_begin());
    for (int i = 0; i < nu; ++i) {
      const double s = static_cast<double>(i) / resolution_u;
      const double u = ku.domain_begin() + s * (ku.domain_end() - ku.domain_begin());
      const nurbs::SurfacePoint p = surface.evaluate(u, v);
      mesh.positions.push_back(p.x);
      mesh.normals.push_back(p.normal);
      mesh.uvs.emplace_back(s, t);
    }
  }
  mesh.face_offsets.reserve(static_cast<size_t>(resolution_u * resolution_v + 1));
  mesh.face_vertices.reserve(static_cast<size_t>(4 * resolution_u * resolution_v));
  for (int j = 0; j < resolution_v; ++j)
    for (int i = 0; i < resolution_u; ++i) {
      const int a = i + nu * j;
      mesh.add_face({a, a + 1, a + 1 + nu, a + nu});  // counter-clockwise about du x dv
    }
  return mesh;
}

}  // namespace shellfrac::render_mesh
