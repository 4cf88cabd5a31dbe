#include "render_mesh/obj_writer.hpp"

#include "render_mesh/number_text.hpp"
#include "render_mesh/object_name.hpp"

namespace shellfrac::render_mesh {

using detail::append_integer;
using detail::append_number;

namespace {

void append_vector(std::string& out, const char* tag, const double* x, int n, int digits) {
  out += tag;
  for (int k = 0; k < n; ++k) {
    out += ' ';
    append_number(out, x[k], digits);
  }
  out += '\n';
}

}  // namespace

std::string obj_text(const std::vector<PolyMesh>& meshes, const ObjSettings& settings) {
  size_t vertices = 0, faces = 0, corners = 0;
  for (const PolyMesh& m : meshes) {
    vertices += m.positions.size();
    faces += static_cast<size_t>(m.num_faces());
    corners += m.face_vertices.size();
  }
  std::string out;
  out.reserve(vertices * 3 * (static_cast<size_t>(settings.significant_digits) + 8) * 3 + corners * 24 + 256);
  out += "# shellfrac render mesh: ";
  append_integer(out, static_cast<long long>(meshes.size()));
  out += " objects, ";
  append_integer(out, static_cast<long long>(vertices));
  out += " vertices in simulation order (never merged), ";
  append_integer(out, static_cast<long long>(faces));
  out += " faces\n";
  if (!settings.material_library.empty()) out += "mtllib " + settings.material_library + "\n";

  const int digits = settings.significant_digits;
  long long v_base = 0, vt_base = 0, vn_base = 0;  // numbers already used, per attribute
  for (size_t i = 0; i < meshes.size(); ++i) {
    const PolyMesh& m = meshes[i];
    const std::string name = export_object_name(m.name, "mesh" + std::to_string(i));
    out += "o " + name + "\ng " + name + "\n";
    if (!settings.material_library.empty()) out += "usemtl shell\n";
    const bool has_uv = !m.positions.empty() && m.uvs.size() == m.positions.size();
    const bool has_normal = !m.positions.empty() && m.normals.size() == m.positions.size();
    for (const Vec3& x : m.positions) append_vector(out, "v", x.data(), 3, digits);
    if (has_uv)
      for (const Vec2& t : m.uvs) append_vector(out, "vt", t.data(), 2, digits);
    if (has_normal)
      for (const Vec3& n : m.normals) append_vector(out, "vn", n.data(), 3, digits);
    for (int f = 0; f < m.num_faces(); ++f) {
      const int b = m.face_offsets[static_cast<size_t>(f)], e = m.face_offsets[static_cast<size_t>(f) + 1];
      const int size = e - b;
      if (size == 0) continue;
      out += size == 1 ? "p" : size == 2 ? "l" : "f";
      for (int k = b; k < e; ++k) {
        const long long v = m.face_vertices[static_cast<size_t>(k)];
        out += ' ';
        append_integer(out, v_base + v + 1);
        if (size < 3) continue;  // points and lines carry positions only
        if (has_uv || has_normal) out += '/';
        if (has_uv) append_integer(out, vt_base + v + 1);
        if (has_normal) {
          out += '/';
          append_integer(out, vn_base + v + 1);
        }
      }
      out += '\n';
    }
    v_base += static_cast<long long>(m.positions.size());
    if (has_uv) vt_base += static_cast<long long>(m.uvs.size());
    if (has_normal) vn_base += static_cast<long long>(m.normals.size());
  }
  return out;
}

std::string obj_material_text() {
  return "# shellfrac material library\n"
         "newmtl shell\n"
         "Ka 0 0 0\n"
         "Kd 0.8 0.8 0.8\n"
         "Ks 0 0 0\n"
         "d 1\n"
         "illum 1\n";
}

}  // namespace shellfrac::render_mesh
