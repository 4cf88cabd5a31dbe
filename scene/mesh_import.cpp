#include "scene/mesh_import.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <utility>

namespace shellfrac::scene {

MeshStats mesh_stats(const TriangleMesh& mesh) {
  MeshStats s;
  bool first = true;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    if (!v.allFinite()) {
      ++s.non_finite_vertices;
      continue;
    }
    s.lo = first ? v : s.lo.cwiseMin(v);
    s.hi = first ? v : s.hi.cwiseMax(v);
    first = false;
  }
  // Vertices at the same position are one vertex here: files split a closed surface's vertices along
  // UV and normal seams (a scanned mesh with texture coordinates), which does not open it.
  std::vector<int> welded(mesh.vertices.size());
  std::map<std::array<double, 3>, int> by_position;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    welded[i] = by_position.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, static_cast<int>(i)).first->second;
  }
  // Each undirected edge counted over the triangles: 2 on a closed manifold surface.
  std::map<std::pair<int, int>, int> uses;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = welded[static_cast<size_t>(t[k])], b = welded[static_cast<size_t>(t[(k + 1) % 3])];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
    const Eigen::Vector3d& p = mesh.vertices[static_cast<size_t>(t[0])];
    const Eigen::Vector3d& q = mesh.vertices[static_cast<size_t>(t[1])];
    const Eigen::Vector3d& r = mesh.vertices[static_cast<size_t>(t[2])];
    s.area += 0.5 * (q - p).cross(r - p).norm();
    s.volume += p.dot(q.cross(r)) / 6.0;  // signed tetrahedron with the origin
  }
  for (const auto& [edge, n] : uses) {
    if (n == 1) ++s.boundary_edges;
    if (n > 2) ++s.non_manifold_edges;
  }
  return s;
}

TriangleMesh import_mesh(const std::string& path, double scale, const Eigen::Vector3d& translate) {
  // Devices, pipes and /proc files would make the importer read without end.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw std::runtime_error("cannot import mesh: " + std::string(std::strerror(errno)));
  if (!S_ISREG(info.st_mode) || info.st_size == 0)
    throw std::runtime_error("cannot import mesh: not a regular, non-empty file");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw std::runtime_error("cannot import mesh: " + std::string(importer.GetErrorString()));
  TriangleMesh out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      out.vertices.push_back(scale * Eigen::Vector3d(p.x, p.y, p.z) + translate);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      out.triangles.emplace_back(base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                                 base + static_cast<int>(face.mIndices[2]));
    }
  }
  if (out.triangles.empty()) throw std::runtime_error("mesh holds no triangles");
  const MeshStats s = mesh_stats(out);
  if (s.non_finite_vertices > 0)
    throw std::runtime_error("mesh has " + std::to_string(s.non_finite_vertices) + " vertices with NaN or infinite coordinates");
  if (s.boundary_edges > 0)
    throw std::runtime_error("mesh is not closed: " + std::to_string(s.boundary_edges) +
                             " boundary edge(s), edges of one triangle only; a level set needs a closed surface (a watertight mesh)");
  const double extent = (s.hi - s.lo).maxCoeff();
  if (!(std::abs(s.volume) > 1e-12 * extent * extent * extent))
    throw std::runtime_error("mesh encloses no volume (" + std::to_string(s.volume) + " m^3): a level set needs a solid");
  return out;
}

}  // namespace shellfrac::scene
