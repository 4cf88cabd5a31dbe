#pragma once
// Cracked physical render mesh of one patch (thesis sec. 4.9, Algorithm 5, Fig. 4.16/4.17).
//
// The work is split into three steps so that each can be tested on its own:
//   1. split_parameter_grid     R x S quads in the parameter rectangle, each quad crossed by the crack
//                               split into polygons (thesis 4.9.2). Vertices are shared.
//   2. separate_crack_vertices  every vertex on the crack gets one shadow copy per side of the crack
//                               (a sector of polygon corners that meet across uncracked edges), moved
//                               by Dv along the sector's bisector into it (thesis 4.9.3, Fig. 4.17).
//   3. cracked_tessellation     world positions from a caller-supplied evaluator (NURBS or MLS, which
//                               sees the shadow uv on the correct side of the crack), normals, UVs.
// See docs/render-mesh.md for the conventions and the degenerate cases.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

// One straight piece of crack in patch parameter coordinates (u, v). Pieces may share end points,
// meet in junctions, cross each other, form closed loops, end inside a quad and run through grid
// vertices or along quad edges.
struct CrackSegment2 {
  Vec2 a, b;
};

// The patch parameter rectangle [u0, u1] x [v0, v1].
struct ParameterDomain {
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
};

struct CrackedTessellationSettings {
  int resolution_u = 1, resolution_v = 1;  // R x S render quads, independent of the simulation
  // Dv of thesis 4.9.3, absolute, in parameter units (the thesis uses 1e-5 on unit patches). Clamped
  // to a quarter of the shortest edge at the vertex and half the clearance to the other edges of the
  // polygons around it, so that a shadow never leaves its polygons.
  double shadow_offset = 1e-5;
};

// A polygon mesh in the parameter plane. Faces are CSR like PolyMesh and counter-clockwise in (u, v).
struct ParameterMesh {
  std::vector<Vec2> uv;                 // patch parameter coordinates (not normalised)
  std::vector<unsigned char> on_crack;  // 1 if the vertex lies on the crack (or is a shadow of one)
  // For a mesh from separate_crack_vertices: the vertex of the split mesh this one was made from.
  // For a split mesh: the identity.
  std::vector<int> source_vertex;
  std::vector<int> face_offsets{0};
  std::vector<int> face_vertices;
  // Per face corner (parallel to face_vertices): 1 if the edge to the next corner lies on the crack.
  std::vector<unsigned char> crack_edge;

  int num_vertices() const { return static_cast<int>(uv.size()); }
  int num_faces() const { return static_cast<int>(face_offsets.size()) - 1; }
};

// Step 1. Without crack the result equals the uncracked R x S grid of tessellate(): (R+1)(S+1)
// vertices numbered i + (R+1) j, R*S quads in row-major order. With a crack, grid vertices keep
// those numbers, the extra vertices (crack points, edge intersections) follow, and every cracked quad
// is replaced by its polygons in place. Crack pieces outside the rectangle, shorter than the merge
// tolerance (1e-6 of a quad side) or lying on the patch boundary are ignored.
// Throws std::invalid_argument for a resolution below 1 or an empty/inverted domain.
ParameterMesh split_parameter_grid(const ParameterDomain& domain, const std::vector<CrackSegment2>& crack,
                                   const CrackedTessellationSettings& settings);

// Step 2. Around each crack vertex, corners joined across edges that are not crack_edge form a sector;
// each sector gets one shadow (so fragments stay watertight), except that a face never takes the same
// shadow twice (a tip exactly on a quad edge splits its sector). Vertices not on the crack keep their
// relative order (an uncracked mesh is unchanged); shadows follow in face order. Faces, their order,
// sizes and crack_edge flags are kept. Throws std::invalid_argument for a negative offset.
ParameterMesh separate_crack_vertices(const ParameterMesh& split, double shadow_offset);

// Step 3, non-template part: UVs normalised to [0, 1] over the domain as in tessellate(); normals
// given per vertex, or (if empty) area-weighted polygon normals averaged at each vertex.
PolyMesh assemble_render_mesh(const ParameterMesh& mesh, const ParameterDomain& domain,
                              std::vector<Vec3> positions, std::vector<Vec3> normals,
                              const std::string& name);

// Step 3. position(const Vec2& uv) -> Vec3 is called once per vertex with the (shadow) parameter
// coordinates. Faces stay counter-clockwise about du x dv, like the uncracked tessellation.
template <class Position>
PolyMesh cracked_tessellation(const ParameterMesh& separated, const ParameterDomain& domain,
                              Position&& position, const std::string& name) {
  std::vector<Vec3> positions;
  positions.reserve(separated.uv.size());
  for (const Vec2& uv : separated.uv) positions.push_back(position(uv));
  return assemble_render_mesh(separated, domain, std::move(positions), {}, name);
}

// As above with a normal evaluator normal(const Vec2& uv) -> Vec3 (e.g. the surface normal).
template <class Position, class Normal>
PolyMesh cracked_tessellation(const ParameterMesh& separated, const ParameterDomain& domain,
                              Position&& position, Normal&& normal, const std::string& name) {
  std::vector<Vec3> positions, normals;
  positions.reserve(separated.uv.size());
  normals.reserve(separated.uv.size());
  for (const Vec2& uv : separated.uv) {
    positions.push_back(position(uv));
    normals.push_back(normal(uv));
  }
  return assemble_render_mesh(separated, domain, std::move(positions), std::move(normals), name);
}

// All three steps (Algorithm 5 for one patch).
template <class Position>
PolyMesh cracked_tessellation(const ParameterDomain& domain, const std::vector<CrackSegment2>& crack,
                              const CrackedTessellationSettings& settings, Position&& position,
                              const std::string& name) {
  const ParameterMesh separated =
      separate_crack_vertices(split_parameter_grid(domain, crack, settings), settings.shadow_offset);
  return cracked_tessellation(separated, domain, std::forward<Position>(position), name);
}

// Number of connected components (fragments) of the faces, two faces being connected when they
// share a vertex index. Vertices used by no face are not counted.
int count_components(const PolyMesh& mesh);
int count_components(const ParameterMesh& mesh);
// World-space area of the faces (each face fan-triangulated from its first vertex): the sheet area
// kept after tearing (thesis Fig. 4.10).
double surface_area(const PolyMesh& mesh);

// Signed area of face f in the parameter plane (shoelace); positive for counter-clockwise faces.
double signed_area(const ParameterMesh& mesh, int face);

}  // namespace shellfrac::render_mesh
