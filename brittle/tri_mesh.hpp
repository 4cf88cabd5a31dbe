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

// Topology and validity of a mesh, with vertices welded by exact position.
struct MeshReport {
  size_t boundary_edges = 0;      // edges used by one triangle
  size_t non_manifold_edges = 0;  // edges used by more than two triangles
  size_t inconsistent_edges = 0;  // edges whose two triangles traverse it in the same direction
  size_t bad_indices = 0;         // triangle corners that name no vertex
  size_t non_finite = 0;          // positions, normals or UVs with NaN or infinity
  size_t degenerate_triangles = 0;
  double volume = 0;              // signed, by the divergence theorem (positive when outward)
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0 && bad_indices == 0; }
};
MeshReport inspect_mesh(const TriMesh& mesh);

// Refuses a mesh that cannot bound a solid: not closed (counts boundary and non-manifold edges), NaN or
// infinite values, bad indices, inconsistent orientation, or a volume that is zero or negative (inside
// out). Throws InputError naming `source` (the file or scene key) and the counts.
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
