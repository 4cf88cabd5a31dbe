#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace shellfrac::render_mesh {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

// A named polygon mesh with per-vertex normals and UVs, the unit of export. Faces are stored CSR-style:
// face f uses face_vertices[face_offsets[f] .. face_offsets[f+1]), counter-clockwise seen from the normal.
struct PolyMesh {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  std::vector<int> face_offsets{0};
  std::vector<int> face_vertices;

  int num_vertices() const { return static_cast<int>(positions.size()); }
  int num_faces() const { return static_cast<int>(face_offsets.size()) - 1; }
  void add_face(std::initializer_list<int> vertices) {
    face_vertices.insert(face_vertices.end(), vertices);
    face_offsets.push_back(static_cast<int>(face_vertices.size()));
  }
};

}  // namespace shellfrac::render_mesh
