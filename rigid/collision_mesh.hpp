#pragma once
// Collision meshes for rigid bodies (thesis sec. 3.6.1): a breakable object keeps its full mesh for
// rendering and mass, and a decimated copy for the rigid-body engine's contact queries.
#include <cstddef>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::rigid {

struct DecimatedMesh {
  brittle::TriMesh mesh;     // welded positions only (no normals or UVs)
  double relative_error = 0;  // meshoptimizer's error, relative to the mesh's extent
};

// The mesh welded by exact position and simplified with meshoptimizer to at most `max_triangles` (the
// face budget N_df) by edge collapses that keep it closed; a mesh already within the budget is only welded.
DecimatedMesh decimate(const brittle::TriMesh& mesh, size_t max_triangles);

// Volume of the convex hull of the mesh's vertices over the mesh's own volume (>= 1; 1 for a convex
// solid). Decides whether a body may collide as its convex hull.
double hull_volume_ratio(const brittle::TriMesh& mesh);

}  // namespace shellfrac::rigid
