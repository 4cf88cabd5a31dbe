#pragma once
// Render-mesh quality metrics: honest piece counts across patches and seams, and stretch
// against the rest configuration. See docs/render-mesh.md, "Quality metrics".
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

// Vertex vertex_a of meshes[mesh_a] and vertex vertex_b of meshes[mesh_b] are the same material point
// (a coupled seam; see seam_joins.hpp).
struct VertexJoin {
  int mesh_a = 0, vertex_a = 0, mesh_b = 0, vertex_b = 0;
};

struct PieceStats {
  int pieces = 0;            // connected components of area >= min_piece_area
  int slivers = 0;           // connected components below it
  double piece_area = 0.0;   // total world area of the pieces
  double sliver_area = 0.0;  // total world area of the slivers
  std::vector<double> component_area;              // per component label
  std::vector<unsigned char> component_is_sliver;  // per component label
  // face_label[m][f]: the component of face f of mesh m; -1 for faces of fewer than 3 corners
  // (points and lines carry no area and are not counted). Labels are numbered in order of their
  // first face (mesh by mesh, face by face), so they are reproducible.
  std::vector<std::vector<int>> face_label;
};

// Connected components of the faces of all meshes: two faces are connected when they share a vertex of
// their mesh, or when vertices of theirs are joined (transitively) by `joins`. The area of a component
// is the world area of its faces (face_area). Throws std::invalid_argument for a join naming a mesh or
// vertex that does not exist, or a negative min_piece_area.
PieceStats piece_stats(const std::vector<PolyMesh>& meshes, const std::vector<VertexJoin>& joins,
                       double min_piece_area);

// World area of face f: the sum of the areas of its triangles (face_triangles).
double face_area(const PolyMesh& mesh, int face);

// Largest singular value of the affine map taking the rest triangle onto the current one (the largest
// principal stretch, sqrt of the largest eigenvalue of C = F^T F). Invariant under rigid motions of
// either triangle. 0 for a rest triangle of zero area (no material to stretch).
double principal_stretch(const Vec3& rest0, const Vec3& rest1, const Vec3& rest2, const Vec3& current0,
                         const Vec3& current1, const Vec3& current2);

struct EdgeStretch {
  double ratio = 0.0;  // largest current length / rest length over the render edges
  int face = -1, corner = -1;  // where: the edge from that corner of that face to the next corner
  double current_length = 0.0, rest_length = 0.0;
};

// Over every render edge (the polygon sides of the mesh, not the diagonals of a triangulation). Edges
// of zero rest length are skipped. A side shorter at rest than kShortSideFraction of the median rest
// side is measured against that length instead: next to a crack a polygon has sides of 1e-9..1e-5 at
// rest (its corners on the crack line and their shadows), whose endpoints come from different bases,
// and a sub-millimetre difference between them would read as a stretch of 1e4 although nothing spans
// a gap. A side that really spans an opened crack is as long as the gap and still reads large. `rest_positions` are the vertices in the rest configuration, with
// the mesh's topology (see docs/render-mesh.md for how to evaluate them). Throws std::invalid_argument
// when the counts differ.
constexpr double kShortSideFraction = 0.1;
EdgeStretch max_edge_stretch(const PolyMesh& current, const std::vector<Vec3>& rest_positions);
// As above with a rest mesh, which must have the same faces (checked).
EdgeStretch max_edge_stretch(const PolyMesh& current, const PolyMesh& rest);

struct StrandStats {
  int faces = 0;                       // faces whose largest principal stretch exceeds the threshold
  double area = 0.0;                   // their world area in the current configuration
  double max_principal_stretch = 0.0;  // over all faces
  int worst_face = -1;
};

// Largest principal stretch of a polygon face: the largest singular value of the affine map F that best
// takes the rest corners (in their own plane) onto the current ones (least squares over the corners).
// Exact for a triangle and for an affinely deformed polygon; unlike the map of each triangle of a
// triangulation, it is not fooled by a thin sub-triangle between two nearly coincident corners (a crack's
// shadow vertices), whose own map is ill-determined. 0 for a degenerate rest polygon.
// A rest polygon whose width (second principal extent) is below kDegenerateWidth of its length counts
// as degenerate (stretch 0).
constexpr double kDegenerateWidth = 1e-6;
double face_stretch(const std::vector<Vec3>& rest, const std::vector<Vec3>& current);

// A face is a strand when its face_stretch exceeds `threshold`; its current area counts. A face whose
// rest diameter is below kShortSideFraction of the median rest side counts with the smaller of its
// face_stretch and its current diameter over that floor (as short sides do in max_edge_stretch).
StrandStats strand_area(const PolyMesh& current, const std::vector<Vec3>& rest_positions, double threshold = 3.0);
StrandStats strand_area(const PolyMesh& current, const PolyMesh& rest, double threshold = 3.0);

}  // namespace shellfrac::render_mesh
