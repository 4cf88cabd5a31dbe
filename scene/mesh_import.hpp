#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace shellfrac::scene {

// Triangles of a mesh file (OBJ, PLY, STL and every format assimp reads), all objects merged, node
// transforms applied, scaled and translated.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

// What a mesh must satisfy to become a level set (solids are sampled inside it, colliders push out of
// it): finite vertices, a closed surface and a volume.
struct MeshStats {
  size_t non_finite_vertices = 0;
  size_t boundary_edges = 0;  // edges used by one triangle only (an open surface)
  size_t non_manifold_edges = 0;  // edges used by more than two triangles
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // bounds of the finite vertices
  double area = 0;    // surface area [m^2]
  double volume = 0;  // enclosed volume [m^3] (divergence theorem; its sign follows the winding)
};

MeshStats mesh_stats(const TriangleMesh& mesh);

// Reads a mesh file. Throws std::runtime_error with the reason (assimp's, or which check failed, with
// counts) when the file cannot be read, holds no triangles, has non-finite vertices, is not closed (has
// boundary edges) or encloses no volume. The caller adds the file name and JSON path.
TriangleMesh import_mesh(const std::string& path, double scale, const Eigen::Vector3d& translate);

}  // namespace shellfrac::scene
