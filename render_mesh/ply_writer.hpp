#pragma once
// shellfrac's own PLY writer. assimp's PLY exporter runs PreTransformVertices, which regroups meshes
// by primitive type and vertex format (a particle cloud moved in front of the shells), so the vertex
// order was not the PolyMesh order.
#include <string>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

struct PlySettings {
  bool binary = false;            // binary_little_endian 1.0, else ascii 1.0
  bool double_precision = false;  // `double` vertex properties (17 digits in ASCII), else `float`
};

// One PLY file for all meshes: a `vertex` element with every vertex of every mesh, mesh after mesh in
// PolyMesh order (x y z; nx ny nz and s t when any mesh has them, 0 where a mesh has none), a `face`
// element with the polygons (3 or more corners, indices into that list), and an `edge` element with the
// two-corner faces. One-corner faces (particles) are the vertices themselves. A comment line per mesh
// gives its name (export_object_name) and its vertex range: "comment object NAME vertices FIRST COUNT".
std::string ply_bytes(const std::vector<PolyMesh>& meshes, const PlySettings& settings);

}  // namespace shellfrac::render_mesh
