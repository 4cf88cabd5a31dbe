#include "render_mesh/gltf_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "render_mesh/number_text.hpp"
#include "render_mesh/object_name.hpp"
#include "render_mesh/triangulation.hpp"

namespace shellfrac::render_mesh {

using detail::append_float;
using detail::append_integer;

namespace {

// glTF enumerations (glTF 2.0 specification, sec. 3.6 and 3.7).
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kPoints = 0, kLines = 1, kTriangles = 4;

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out += static_cast<char>((v >> (8 * k)) & 0xFFu);  // little endian
}

void put_f32(std::string& out, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof(bits));
  put_u32(out, bits);
}

void append_json_string(std::string& out, const std::string& s) {
  out += '"';
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {  // export_object_name removes these; kept correct for any input
      static const char* hex = "0123456789abcdef";
      out += "\\u00";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += ch;
    }
  }
  out += '"';
}

// Accumulates the binary buffer and the bufferView / accessor JSON that describe it.
class BufferBuilder {
 public:
  // Appends one bufferView + accessor; returns the accessor index. `bytes` is 4-byte aligned.
  int add(std::string bytes, int count, const char* type, int component, int target, const std::string& extra = {}) {
    const size_t offset = binary_.size();
    binary_ += bytes;
    if (!views_.empty()) views_ += ',';
    views_ += "{\"buffer\":0,\"byteOffset\":";
    append_integer(views_, static_cast<long long>(offset));
    views_ += ",\"byteLength\":";
    append_integer(views_, static_cast<long long>(bytes.size()));
    if (target) {  // animation data has no target (glTF 2.0, sec. 3.6.2)
      views_ += ",\"target\":";
      append_integer(views_, target);
    }
    views_ += '}';
    if (!accessors_.empty()) accessors_ += ',';
    accessors_ += "{\"bufferView\":";
    append_integer(accessors_, num_);
    accessors_ += ",\"componentType\":";
    append_integer(accessors_, component);
    accessors_ += ",\"count\":";
    append_integer(accessors_, count);
    accessors_ += ",\"type\":\"";
    accessors_ += type;
    accessors_ += '"';
    accessors_ += extra;
    accessors_ += '}';
    return num_++;
  }
  const std::string& binary() const { return binary_; }
  const std::string& views() const { return views_; }
  const std::string& accessors() const { return accessors_; }
  bool empty() const { return num_ == 0; }

 private:
  std::string binary_, views_, accessors_;
  int num_ = 0;
};

std::string float_array(const float* v, int n) {
  std::string out = "[";
  for (int k = 0; k < n; ++k) {
    if (k) out += ',';
    append_float(out, v[k]);
  }
  return out + "]";
}

// POSITION accessor: the positions as floats, with the min/max the specification requires (over the
// finite values; a non-finite coordinate cannot be written in JSON).
int add_positions(BufferBuilder& buffer, const PolyMesh& m) {
  std::string bytes;
  bytes.reserve(m.positions.size() * 12);
  float lo[3], hi[3];
  bool any[3] = {false, false, false};
  for (const Vec3& x : m.positions)
    for (int c = 0; c < 3; ++c) {
      const auto f = static_cast<float>(x[c]);
      put_f32(bytes, f);
      if (!std::isfinite(f)) continue;
      lo[c] = any[c] ? std::min(lo[c], f) : f;
      hi[c] = any[c] ? std::max(hi[c], f) : f;
      any[c] = true;
    }
  for (int c = 0; c < 3; ++c)
    if (!any[c]) lo[c] = hi[c] = 0.0f;
  const std::string extra = ",\"min\":" + float_array(lo, 3) + ",\"max\":" + float_array(hi, 3);
  return buffer.add(std::move(bytes), m.num_vertices(), "VEC3", kFloat, kArrayBuffer, extra);
}

int add_normals(BufferBuilder& buffer, const PolyMesh& m) {
  std::string bytes;
  bytes.reserve(m.normals.size() * 12);
  for (const Vec3& n : m.normals) {
    const double length = n.norm();
    const Vec3 unit = length > 0.0 && std::isfinite(length) ? Vec3(n / length) : Vec3::UnitZ();  // spec: unit length
    for (int c = 0; c < 3; ++c) put_f32(bytes, static_cast<float>(unit[c]));
  }
  return buffer.add(std::move(bytes), m.num_vertices(), "VEC3", kFloat, kArrayBuffer);
}

int add_uvs(BufferBuilder& buffer, const PolyMesh& m) {
  std::string bytes;
  bytes.reserve(m.uvs.size() * 8);
  for (const Vec2& t : m.uvs) {
    put_f32(bytes, static_cast<float>(t.x()));
    put_f32(bytes, static_cast<float>(1.0 - t.y()));
  }
  return buffer.add(std::move(bytes), m.num_vertices(), "VEC2", kFloat, kArrayBuffer);
}

}  // namespace

std::string uri_escape(const std::string& text) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    const bool alnum = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    if (alnum || c == '-' || c == '.' || c == '_' || c == '~') {
      out += ch;
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

// Animation of the nodes with keys: samplers and channels of one animation (glTF 2.0, sec. 3.11).
std::string animation_json(BufferBuilder& buffer, const std::vector<NodeTrack>& tracks) {
  std::string samplers, channels;
  int sampler = 0;
  for (size_t node = 0; node < tracks.size(); ++node) {
    const NodeTrack& t = tracks[node];
    if (t.times.empty()) continue;
    const int n = static_cast<int>(t.times.size());
    std::string times;
    for (float x : t.times) put_f32(times, x);
    const float lo = t.times.front(), hi = t.times.back();
    const int input = buffer.add(std::move(times), n, "SCALAR", kFloat, 0,
                                 ",\"min\":" + float_array(&lo, 1) + ",\"max\":" + float_array(&hi, 1));
    std::string tr, rot, scale;
    for (int k = 0; k < n; ++k) {
      for (int c = 0; c < 3; ++c) put_f32(tr, static_cast<float>(t.translations[static_cast<size_t>(k)][c]));
      const Eigen::Quaterniond& q = t.rotations[static_cast<size_t>(k)];
      for (double c : {q.x(), q.y(), q.z(), q.w()}) put_f32(rot, static_cast<float>(c));
      for (int c = 0; c < 3; ++c) put_f32(scale, t.scales[static_cast<size_t>(k)]);
    }
    const int outputs[3] = {buffer.add(std::move(tr), n, "VEC3", kFloat, 0), buffer.add(std::move(rot), n, "VEC4", kFloat, 0),
                            buffer.add(std::move(scale), n, "VEC3", kFloat, 0)};
    const char* paths[3] = {"translation", "rotation", "scale"};
    for (int c = 0; c < 3; ++c) {
      if (!samplers.empty()) samplers += ',', channels += ',';
      samplers += "{\"input\":";
      append_integer(samplers, input);
      samplers += ",\"output\":";
      append_integer(samplers, outputs[c]);
      samplers += c == 2 ? ",\"interpolation\":\"STEP\"}" : ",\"interpolation\":\"LINEAR\"}";
      channels += "{\"sampler\":";
      append_integer(channels, sampler++);
      channels += ",\"target\":{\"node\":";
      append_integer(channels, static_cast<long long>(node));
      channels += ",\"path\":\"";
      channels += paths[c];
      channels += "\"}}";
    }
  }
  if (samplers.empty()) return "";
  return "{\"name\":\"motion\",\"samplers\":[" + samplers + "],\"channels\":[" + channels + "]}";
}

namespace {

// The vertex attributes of mesh m (positions; normals and UVs when every vertex has one) as a JSON object
// of accessor numbers.
std::string mesh_attributes(BufferBuilder& buffer, const PolyMesh& m) {
  std::string attributes = "{\"POSITION\":";
  append_integer(attributes, add_positions(buffer, m));
  if (m.normals.size() == m.positions.size()) {
    attributes += ",\"NORMAL\":";
    append_integer(attributes, add_normals(buffer, m));
  }
  if (m.uvs.size() == m.positions.size()) {
    attributes += ",\"TEXCOORD_0\":";
    append_integer(attributes, add_uvs(buffer, m));
  }
  attributes += '}';
  return attributes;
}

// The primitives of mesh m: one per primitive mode present (triangles, lines, points), index lists in face
// order; vertices without faces are drawn as points.
std::string mesh_primitives(BufferBuilder& buffer, const PolyMesh& m, const std::string& attributes) {
  const Triangulation tri = triangulate(m);
  std::string indices[3];  // points, lines, triangles
  int counts[3] = {0, 0, 0};
  for (int f = 0; f < tri.mesh.num_faces(); ++f) {
    const int b = tri.mesh.face_offsets[static_cast<size_t>(f)], e = tri.mesh.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b < 1 || e - b > 3) continue;
    const int kind = e - b - 1;
    for (int k = b; k < e; ++k) put_u32(indices[kind], static_cast<std::uint32_t>(tri.mesh.face_vertices[static_cast<size_t>(k)]));
    counts[kind] += e - b;
  }
  std::string primitives;
  auto add_primitive = [&](int mode, int index_accessor) {
    if (!primitives.empty()) primitives += ',';
    primitives += "{\"attributes\":" + attributes;
    if (index_accessor >= 0) {
      primitives += ",\"indices\":";
      append_integer(primitives, index_accessor);
    }
    primitives += ",\"material\":0,\"mode\":";
    append_integer(primitives, mode);
    primitives += '}';
  };
  const int modes[3] = {kPoints, kLines, kTriangles};
  for (int kind : {2, 1, 0})
    if (counts[kind] > 0)
      add_primitive(modes[kind], buffer.add(std::move(indices[kind]), counts[kind], "SCALAR", kUnsignedInt, kElementArrayBuffer));
  if (primitives.empty()) add_primitive(kPoints, -1);
  return primitives;
}

// The document's JSON around its parts (glTF 2.0): asset, scene, nodes, meshes with one double-sided
// material, the animation, and the buffer's accessors and views.
std::string document_json(const std::string& scene_nodes, const std::string& nodes, const std::string& gltf_meshes,
                          const std::string& animation, const BufferBuilder& buffer, const std::string& buffer_uri) {
  std::string j = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"shellfrac\"},\"scene\":0,\"scenes\":[{";
  if (!scene_nodes.empty()) j += "\"nodes\":[" + scene_nodes + "]";
  j += "}]";
  if (!nodes.empty()) j += ",\"nodes\":[" + nodes + "]";
  if (!gltf_meshes.empty()) {
    j += ",\"meshes\":[" + gltf_meshes + "]";
    j += ",\"materials\":[{\"name\":\"shell\",\"doubleSided\":true,\"pbrMetallicRoughness\":"
         "{\"baseColorFactor\":[0.8,0.8,0.8,1],\"metallicFactor\":0,\"roughnessFactor\":0.5}}]";
  }
  if (!animation.empty()) j += ",\"animations\":[" + animation + "]";
  if (!buffer.empty()) {
    j += ",\"accessors\":[" + buffer.accessors() + "]";
    j += ",\"bufferViews\":[" + buffer.views() + "]";
    j += ",\"buffers\":[{\"byteLength\":";
    append_integer(j, static_cast<long long>(buffer.binary().size()));
    if (!buffer_uri.empty()) {
      j += ",\"uri\":";
      append_json_string(j, uri_escape(buffer_uri));
    }
    j += "}]";
  }
  j += "}\n";
  return j;
}

}  // namespace

GltfDocument gltf_document(const std::vector<PolyMesh>& meshes, const std::string& buffer_uri,
                           const std::vector<NodeTrack>& tracks) {
  if (!tracks.empty() && tracks.size() != meshes.size())
    throw std::invalid_argument("glTF writer: one track per mesh is needed (" + std::to_string(tracks.size()) +
                                " for " + std::to_string(meshes.size()) + ")");
  BufferBuilder buffer;
  std::string nodes, gltf_meshes, scene_nodes;
  int mesh_count = 0;
  for (size_t i = 0; i < meshes.size(); ++i) {
    const std::string name = export_object_name(meshes[i].name, "mesh" + std::to_string(i));
    if (i) nodes += ',', scene_nodes += ',';
    append_integer(scene_nodes, static_cast<long long>(i));
    nodes += "{\"name\":";
    append_json_string(nodes, name);
    const PolyMesh& m = meshes[i];
    if (m.positions.empty()) {  // nothing to draw: a named node without a mesh
      nodes += '}';
      continue;
    }
    nodes += ",\"mesh\":";
    append_integer(nodes, mesh_count++);
    nodes += '}';
    const std::string attributes = mesh_attributes(buffer, m);
    const std::string primitives = mesh_primitives(buffer, m, attributes);
    if (!gltf_meshes.empty()) gltf_meshes += ',';
    gltf_meshes += "{\"name\":";
    append_json_string(gltf_meshes, name);
    gltf_meshes += ",\"primitives\":[" + primitives + "]}";
  }
  const std::string animation = animation_json(buffer, tracks);
  GltfDocument doc;
  doc.json = document_json(scene_nodes, nodes, gltf_meshes, animation, buffer, buffer_uri);
  doc.binary = buffer.binary();
  return doc;
}

std::string glb_container(const GltfDocument& document) {
  // GLB layout (glTF 2.0 sec. 4.4): 12-byte header, JSON chunk padded with spaces, BIN chunk padded
  // with zeros, every chunk a multiple of 4 bytes.
  std::string json = document.json;
  while (json.size() % 4) json += ' ';
  std::string bin = document.binary;
  while (bin.size() % 4) bin += '\0';
  const size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::runtime_error("glTF binary container above 4 GiB (" + std::to_string(total) + " bytes)");
  std::string out;
  out.reserve(total);
  put_u32(out, 0x46546C67u);  // "glTF"
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(total));
  put_u32(out, static_cast<std::uint32_t>(json.size()));
  put_u32(out, 0x4E4F534Au);  // "JSON"
  out += json;
  if (!bin.empty()) {
    put_u32(out, static_cast<std::uint32_t>(bin.size()));
    put_u32(out, 0x004E4942u);  // "BIN\0"
    out += bin;
  }
  return out;
}

}  // namespace shellfrac::render_mesh
