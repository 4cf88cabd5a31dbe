#pragma once
#include <cstddef>
#include <string>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// What repair_closed_solid changed, counted against its input.
struct MeshRepair {
  size_t removed_vertices = 0;    // coincident vertices merged into one, and vertices no triangle used
  size_t removed_triangles = 0;   // duplicate, collapsed and zero-area triangles dropped
  size_t split_vertices = 0;      // vertices duplicated to pull non-manifold parts apart
  size_t stitched_edges = 0;      // pairs of coincident boundary edges sewn together
  size_t reversed_triangles = 0;  // input triangles the output holds in the opposite orientation
  bool changed() const;
  // "1 triangle reversed, 12 coincident or unused vertices removed"; "nothing changed".
  std::string describe() const;
};

// A closed, outward-oriented manifold made from a mesh with CGAL Polygon Mesh Processing: the mesh as a
// polygon soup is repaired (duplicates and degenerate polygons), oriented consistently, turned into a
// surface, its coincident borders stitched, its degenerate faces removed and its components oriented to
// bound a volume. Vertex positions are never moved, so the volume is that of the input's solid. The
// result has positions and triangles only (normals and UVs are dropped). Throws InputError, naming
// `source` and the counts as require_closed_solid does, when the result still cannot be broken (holes,
// parts touching at a point or an edge, zero volume), or when the input has NaN or bad indices.
TriMesh repair_closed_solid(const TriMesh& mesh, const std::string& source, MeshRepair& changes);

}  // namespace shellfrac::brittle
