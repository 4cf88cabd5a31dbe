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

// Throws std::runtime_error with assimp's reason when the file cannot be read or holds no triangles.
TriangleMesh import_mesh(const std::string& path, double scale, const Eigen::Vector3d& translate);

}  // namespace shellfrac::scene
