#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace shellfrac::brittle {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Mat3 = Eigen::Matrix3d;
using Tri = Eigen::Vector3i;

// A plain indexed triangle mesh with optional per-vertex normals and UVs (empty, or one per position),
// the unit the brittle path reads (the object to break) and writes (fragments, crack surfaces). Vertices
// may be split at attribute seams; topology checks weld them by position.
struct TriMesh {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;  // counter-clockwise seen from outside
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;

  size_t num_vertices() const { return positions.size(); }
  size_t num_triangles() const { return triangles.size(); }
  bool has_normals() const { return !normals.empty() && normals.size() == positions.size(); }
  bool has_uvs() const { return !uvs.empty() && uvs.size() == positions.size(); }
  // Appends another mesh (attributes kept only when both have them).
  void append(const TriMesh& other);
};

// Topology and validity of a mesh, with vertices welded by exact position: the view of the exact cutter
// (cut_exact.cpp), which welds the same way and skips triangles whose corners weld together.
struct MeshReport {
  size_t boundary_edges = 0;         // edges used by one triangle (holes)
  size_t non_manifold_edges = 0;     // edges used by more than two triangles
  size_t non_manifold_vertices = 0;  // vertices whose triangles, joined across the edges at the vertex, form
                                     // more than one fan (two solids touching at a point)
  size_t inconsistent_edges = 0;     // edges whose two triangles traverse it in the same direction
  size_t bad_indices = 0;            // triangle corners that name no vertex
  size_t non_finite = 0;             // positions, normals or UVs with NaN or infinity
  size_t degenerate_triangles = 0;   // zero area (collapsed ones, with corners welded together, included)
  double volume = 0;                 // signed, by the divergence theorem (positive when outward)
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0 && bad_indices == 0; }
  // Closed, one fan at every vertex and consistently oriented: what the exact cutter can take.
  bool closed_manifold() const { return closed() && non_manifold_vertices == 0 && inconsistent_edges == 0; }
};
MeshReport inspect_mesh(const TriMesh& mesh);

// Refuses a mesh that cannot bound a solid: no triangles, bad indices, NaN or infinite values, not a
// closed manifold (every count of boundary edges, non-manifold edges, non-manifold vertices and
// inconsistently oriented edges that is not zero), or a volume that is zero or negative (inside out).
// Throws InputError naming `source` (the file or scene key) and the counts.
void require_closed_solid(const TriMesh& mesh, const std::string& source);

// Volume, centre of mass, mass and inertia tensor (about the centre of mass, world axes) of the solid a
// closed mesh bounds, for a uniform density.
struct MassProperties {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  double mass = 0;
  Mat3 inertia = Mat3::Zero();
};
MassProperties mass_properties(const TriMesh& mesh, double density);

double surface_area(const TriMesh& mesh);
void bounding_box(const TriMesh& mesh, Vec3& lo, Vec3& hi);
// Area-weighted vertex normals from the triangles (replaces mesh.normals).
void compute_vertex_normals(TriMesh& mesh);

}  // namespace shellfrac::brittle
