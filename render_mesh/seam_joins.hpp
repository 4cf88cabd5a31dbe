#pragma once
// Vertex joins across a coupled seam, for piece_stats (the render meshes of two patches are separate
// meshes; the seam makes them one body until a crack crosses it).
#include <vector>

#include "render_mesh/mesh_quality.hpp"

namespace shellfrac::render_mesh {

// A side of the normalised UV square [0, 1]^2 of a render mesh (UVs as tessellate() and the cracked
// tessellation write them).
enum class UvSide { u_min, u_max, v_min, v_max };

// A render vertex on a seam and its coordinate along the seam.
struct SeamVertex {
  int vertex = 0;
  double along = 0.0;
};

// The vertices of `mesh` used by a face of 3 or more corners whose UV lies within `tolerance` of
// `side`, with `along` set to the other normalised UV coordinate (v on a u side, u on a v side), in
// vertex order. The caller maps `along` into the seam's own chart (coupling::seam_coordinate) before
// seam_joins. A tolerance of a few shadow offsets (in normalised UV) takes in the shadow vertices of a
// crack that ends on the seam and nothing else.
std::vector<SeamVertex> side_vertices(const PolyMesh& mesh, UvSide side, double tolerance);

// Joins each vertex of side `a` (of meshes[mesh_a]) to the vertex of side `b` (of meshes[mesh_b]) nearest
// to it in `along`, unless that distance exceeds `max_gap` or a crack crossing of the seam
// (`crack_along`, same chart) lies strictly between the two. Both sides' `along` must be in one chart.
std::vector<VertexJoin> seam_joins(int mesh_a, const std::vector<SeamVertex>& a, int mesh_b,
                                   const std::vector<SeamVertex>& b, const std::vector<double>& crack_along,
                                   double max_gap);

}  // namespace shellfrac::render_mesh
