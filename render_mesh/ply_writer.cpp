#include "render_mesh/ply_writer.hpp"

#include <cstdint>
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "render_mesh/number_text.hpp"
#include "render_mesh/object_name.hpp"

namespace shellfrac::render_mesh {

using detail::append_integer;
using detail::append_number;

namespace {

template <class T>
void put_le(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  // Little endian regardless of the host: reorder on a big-endian machine.
  const std::uint16_t probe = 1;
  const bool little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  for (size_t k = 0; k < sizeof(T); ++k) out += static_cast<char>(bytes[little ? k : sizeof(T) - 1 - k]);
}

class Sink {
 public:
  Sink(const PlySettings& s, std::string& out) : s_(s), out_(out) {}
  void real(double v, bool first) {
    if (s_.binary) {
      s_.double_precision ? put_le(out_, v) : put_le(out_, static_cast<float>(v));
      return;
    }
    if (!first) out_ += ' ';
    append_number(out_, v, s_.double_precision ? 17 : 9);
  }
  void count(std::uint32_t n, bool wide) {
    if (s_.binary) {
      wide ? put_le(out_, n) : put_le(out_, static_cast<std::uint8_t>(n));
      return;
    }
    append_integer(out_, n);
  }
  void index(std::int32_t v) {
    if (s_.binary) {
      put_le(out_, v);
      return;
    }
    out_ += ' ';
    append_integer(out_, v);
  }
  void end_record() {
    if (!s_.binary) out_ += '\n';
  }

 private:
  const PlySettings& s_;
  std::string& out_;
};

}  // namespace

std::string ply_bytes(const std::vector<PolyMesh>& meshes, const PlySettings& settings) {
  size_t vertices = 0, polygons = 0, edges = 0;
  int widest = 0;
  bool normals = false, uvs = false;
  for (const PolyMesh& m : meshes) {
    vertices += m.positions.size();
    normals = normals || (!m.positions.empty() && m.normals.size() == m.positions.size());
    uvs = uvs || (!m.positions.empty() && m.uvs.size() == m.positions.size());
    for (int f = 0; f < m.num_faces(); ++f) {
      const int size = m.face_offsets[static_cast<size_t>(f) + 1] - m.face_offsets[static_cast<size_t>(f)];
      polygons += size >= 3 ? 1 : 0;
      edges += size == 2 ? 1 : 0;
      widest = std::max(widest, size);
    }
  }
  if (vertices > 0x7FFFFFFFu) throw std::runtime_error("PLY: " + std::to_string(vertices) + " vertices exceed 32-bit indices");
  const bool wide_lists = widest > 255;
  const char* real = settings.double_precision ? "double" : "float";

  std::string out = "ply\nformat ";
  out += settings.binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  out += "comment shellfrac render mesh: vertices in simulation order, never merged\n";
  size_t first = 0;
  for (size_t i = 0; i < meshes.size(); ++i) {
    out += "comment object " + export_object_name(meshes[i].name, "mesh" + std::to_string(i)) + " vertices ";
    append_integer(out, static_cast<long long>(first));
    out += ' ';
    append_integer(out, static_cast<long long>(meshes[i].positions.size()));
    out += '\n';
    first += meshes[i].positions.size();
  }
  out += "element vertex " + std::to_string(vertices) + "\n";
  for (const char* p : {"x", "y", "z"}) out += std::string("property ") + real + " " + p + "\n";
  if (normals)
    for (const char* p : {"nx", "ny", "nz"}) out += std::string("property ") + real + " " + p + "\n";
  if (uvs)
    for (const char* p : {"s", "t"}) out += std::string("property ") + real + " " + p + "\n";
  out += "element face " + std::to_string(polygons) + "\n";
  out += std::string("property list ") + (wide_lists ? "uint" : "uchar") + " int vertex_indices\n";
  if (edges) out += "element edge " + std::to_string(edges) + "\nproperty int vertex1\nproperty int vertex2\n";
  out += "end_header\n";

  Sink sink(settings, out);
  for (const PolyMesh& m : meshes) {
    const bool has_normal = m.normals.size() == m.positions.size();
    const bool has_uv = m.uvs.size() == m.positions.size();
    for (size_t k = 0; k < m.positions.size(); ++k) {
      for (int c = 0; c < 3; ++c) sink.real(m.positions[k][c], c == 0);
      if (normals)
        for (int c = 0; c < 3; ++c) sink.real(has_normal ? m.normals[k][c] : 0.0, false);
      if (uvs)
        for (int c = 0; c < 2; ++c) sink.real(has_uv ? m.uvs[k][c] : 0.0, false);
      sink.end_record();
    }
  }
  for (int pass = 0; pass < 2; ++pass) {  // polygons, then edges
    long long base = 0;
    for (const PolyMesh& m : meshes) {
      for (int f = 0; f < m.num_faces(); ++f) {
        const int b = m.face_offsets[static_cast<size_t>(f)], e = m.face_offsets[static_cast<size_t>(f) + 1];
        if (pass == 0 ? e - b < 3 : e - b != 2) continue;
        if (pass == 0) sink.count(static_cast<std::uint32_t>(e - b), wide_lists);
        for (int k = b; k < e; ++k) {
          const long long v = base + m.face_vertices[static_cast<size_t>(k)];
          if (!settings.binary && pass == 1 && k == b)
            append_integer(out, v);  // edge records have no leading count
          else
            sink.index(static_cast<std::int32_t>(v));
        }
        sink.end_record();
      }
      base += static_cast<long long>(m.positions.size());
    }
  }
  return out;
}

}  // namespace shellfrac::render_mesh
