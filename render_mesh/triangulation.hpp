#pragma once
// Deterministic triangulation of render polygons, for formats that take only triangles and for the
// per-triangle quality metrics. See docs/render-mesh.md, "Triangulation".
#include <array>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

// Ear clipping of one simple polygon given by its corners in order (either orientation; collinear
// corners, as where the cracked tessellation splits a quad edge, are allowed). Returns n - 2 triangles
// as corner numbers 0..n-1, each listed in polygon order, so it winds like the polygon. An ear is a
// strictly convex corner whose triangle holds no other corner (closed test); among the ears the one
// with the best shape (4 sqrt(3) area / sum of squared sides) is cut, ties going to the lowest corner,
// so the result is a function of the corner coordinates only. A fan is not used: it fails on the
// non-convex polygons around crack tips. If rounding leaves no valid ear (degenerate input), the most
// convex corner is cut, so n - 2 triangles always come back. Fewer than 3 corners give none.
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec2>& corners);

// The plane in which face f is triangulated: the vertices' UVs when the mesh has one per vertex (the
// patch parameter plane, where the cracked tessellation's polygons are simple and which does not move
// between frames, so the triangles stay the same while the crack is unchanged); otherwise the positions
// projected onto the plane normal to the face's Newell normal.
std::vector<Vec2> face_plane_corners(const PolyMesh& mesh, int face);

// Triangles of face f as vertex indices of the mesh (a triangle gives itself; points and lines none).
std::vector<std::array<int, 3>> face_triangles(const PolyMesh& mesh, int face);

struct Triangulation {
  // The input with every face of more than 3 corners replaced, in place, by its triangles. Vertices
  // (count and order), normals, UVs and the name are unchanged; points, lines and triangles are kept.
  PolyMesh mesh;
  std::vector<int> source_face;  // per face of `mesh`: the input face it comes from
};
Triangulation triangulate(const PolyMesh& mesh);

}  // namespace shellfrac::render_mesh
