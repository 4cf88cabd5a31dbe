#pragma once
// shellfrac's own glTF 2.0 writer. assimp's glTF 2 exporters always run JoinIdenticalVertices (it merges
// vertices closer than 1e-5 in position, normal and UV: shadow vertices of a closed crack) and write the
// vertices in face-corner order, so neither count nor order survived export.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

struct GltfDocument {
  std::string json;    // the glTF JSON
  std::string binary;  // buffer 0 (little-endian floats and 32-bit indices)
};

// The rigid motion of one node over time, as glTF animation keys (one per time, seconds increasing):
// translation and rotation interpolated linearly, scale stepped (0 hides a piece before it exists or
// after it broke). Empty: the node does not move.
struct NodeTrack {
  std::vector<float> times;
  std::vector<Eigen::Vector3d> translations;
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<float> scales;
};

// One node and one mesh per PolyMesh (name = export_object_name), in order. Every mesh keeps all its
// vertices in PolyMesh order as one POSITION accessor (float, with min/max), plus NORMAL (normalised)
// and TEXCOORD_0 (t = 1 - v: glTF's texture origin is the top left) when there is one per vertex. Faces
// become primitives sharing those accessors: polygons triangulated with triangulate() (mode 4), lines
// (mode 1) and points (mode 0), in face order within each. One material "shell", double sided.
// `buffer_uri` names the external .bin file (.gltf); empty means the buffer is a GLB's BIN chunk.
// `tracks`, when given, holds one NodeTrack per mesh: one animation "motion" with a translation, rotation
// and scale channel for every node whose track has keys.
GltfDocument gltf_document(const std::vector<PolyMesh>& meshes, const std::string& buffer_uri,
                           const std::vector<NodeTrack>& tracks = {});

// The binary container (.glb) of a document made with an empty buffer_uri.
std::string glb_container(const GltfDocument& document);

// `text` as a URI reference: every byte outside A-Z a-z 0-9 - . _ ~ is percent-encoded.
std::string uri_escape(const std::string& text);

}  // namespace shellfrac::render_mesh
