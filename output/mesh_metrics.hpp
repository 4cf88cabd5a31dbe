#pragma once
// What the render mesh of a frame shows: the pieces it falls into across patches and coupled
// seams, the slivers too small to count as pieces, and how far its faces are stretched against the rest
// mesh. A strand of fully damaged material joining two fragments shows up here, whatever the crack
// counters say. docs/cli.md ("metrics") defines each number.
#include <vector>

#include "output/frame_render.hpp"
#include "render_mesh/mesh_quality.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

struct MeshQuality {
  int pieces = 0;           // connected components of at least one grid cell (dx^2) of area
  int slivers = 0;          // smaller components
  double sliver_area = 0;   // their total area [m^2]
  std::vector<double> piece_areas;  // area of each piece [m^2], in label order
  double max_edge_stretch = 0;      // largest render-edge length over its rest length
  double strand_area = 0;           // area of faces stretched beyond their material's strand_stretch [m^2]
  int strand_faces = 0;
  double max_principal_stretch = 0;  // largest principal stretch of any render face
};

// The vertex joins of every coupled seam: render vertices of the two patches at the same seam coordinate,
// unless a crack crossing of the seam lies between them, or the two have moved apart by more than a
// quarter of a render edge. The second rule matters where the two patches' cracks meet the seam at
// slightly different points: the seam between the crossings is released (no coupled control point is
// left there), so the pieces on either side separate although no crossing lies between their vertices.
std::vector<render_mesh::VertexJoin> seam_vertex_joins(const sim::Simulation& sim, const FrameMeshes& frame);

// Quality of the shells' meshes of `frame` (the solids' point clouds carry no area and are not counted).
MeshQuality measure_mesh_quality(const sim::Simulation& sim, const FrameMeshes& frame);

}  // namespace shellfrac::output
