#pragma once
// shellfrac's own Wavefront OBJ writer (assimp's merges coincident vertices, so the vertex count of a
// frame changed while the crack did not; docs/render-mesh.md).
#include <string>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

struct ObjSettings {
  std::string material_library;  // file name written as `mtllib`; empty: no material file (objnomtl)
  int significant_digits = 9;    // 9 restores a float exactly, 17 a double
};

// The OBJ text of the meshes. Per mesh, in order: `o NAME` and `g NAME` (NAME = export_object_name),
// `usemtl shell` if there is a material library, one `v` per vertex in PolyMesh order (never merged or
// reordered), `vt` and `vn` when the mesh has one UV / normal per vertex, then the faces in order:
// `f v/vt/vn ...` (indices 1-based over the whole file, the same vertex number for all three), `l` for
// two-corner faces, `p` for one-corner faces (solid particles).
std::string obj_text(const std::vector<PolyMesh>& meshes, const ObjSettings& settings);

// The material library referenced by obj_text: one grey diffuse material "shell".
std::string obj_material_text();

}  // namespace shellfrac::render_mesh
