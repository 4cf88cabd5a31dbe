#include "render_mesh/exporter.hpp"

#include <assimp/Exporter.hpp>

#include <array>
#include <stdexcept>

#include "render_mesh/assimp_export.hpp"
#include "render_mesh/atomic_write.hpp"
#include "render_mesh/gltf_writer.hpp"
#include "render_mesh/obj_writer.hpp"
#include "render_mesh/ply_writer.hpp"
#include "render_mesh/triangulation.hpp"

namespace shellfrac::render_mesh {

namespace fs = std::filesystem;

namespace {

bool one_of(const std::string& id, std::initializer_list<const char*> ids) {
  for (const char* s : ids)
    if (id == s) return true;
  return false;
}

// Properties of the formats, from assimp 5.2's exporter table (the post-processing each exporter
// enforces) and from reading the files back in export_topology_test.cpp.
ExportFormat describe(const std::string& id, const std::string& extension, const std::string& description) {
  ExportFormat f{id, extension, description};
  f.own_writer = one_of(id, {"obj", "objnomtl", "ply", "plyb", "gltf2", "glb2"});
  // gltf/glb (glTF 1) and 3ds enforce JoinIdenticalVertices and stl has no shared vertices at all:
  // those never keep the vertices. assimp's ply exporter regroups meshes by primitive type
  // (PreTransformVertices), hence shellfrac's own PLY writer. The other assimp formats are flagged only
  // where a test reads them back.
  f.keeps_vertices = f.own_writer || one_of(id, {"assbin", "x3d"});
  f.needs_triangles = one_of(id, {"gltf2", "glb2", "gltf", "glb", "stl", "stlb", "3ds", "x3d"});
  f.double_precision = one_of(id, {"obj", "objnomtl", "ply", "plyb"});
  if (id == "obj") f.description = "Wavefront OBJ format (shellfrac writer)";
  if (id == "objnomtl") f.description = "Wavefront OBJ format without material file (shellfrac writer)";
  if (id == "ply") f.description = "Stanford Polygon Library (shellfrac writer)";
  if (id == "plyb") f.description = "Stanford Polygon Library (binary, shellfrac writer)";
  if (id == "gltf2") f.description = "GL Transmission Format v. 2 (shellfrac writer)";
  if (id == "glb2") f.description = "GL Transmission Format v. 2 (binary, shellfrac writer)";
  return f;
}

void check_stem(const std::string& stem) {
  bool plain = !stem.empty() && stem != "." && stem != "..";
  for (const char c : stem) plain = plain && c != '/' && static_cast<unsigned char>(c) >= 0x20 && c != 0x7F;
  if (!plain) throw std::invalid_argument("export file stem \"" + stem + "\" is not a plain file name");
}

void check_mesh(const PolyMesh& m, size_t index) {
  const auto where = [&] { return "mesh " + std::to_string(index) + " (\"" + m.name + "\")"; };
  if (m.face_offsets.empty() || m.face_offsets.front() != 0 ||
      m.face_offsets.back() != static_cast<int>(m.face_vertices.size()))
    throw std::invalid_argument(where() + ": face offsets do not cover the face vertex list");
  for (size_t f = 0; f + 1 < m.face_offsets.size(); ++f)
    if (m.face_offsets[f + 1] < m.face_offsets[f])
      throw std::invalid_argument(where() + ": face " + std::to_string(f) + " has a negative size");
  for (const int v : m.face_vertices)
    if (v < 0 || v >= m.num_vertices())
      throw std::invalid_argument(where() + ": face vertex " + std::to_string(v) + " outside its " +
                                  std::to_string(m.num_vertices()) + " vertices");
}

// The mesh with its one- and two-corner faces removed; vertices unchanged.
PolyMesh without_points_and_lines(const PolyMesh& m) {
  PolyMesh out = m;
  out.face_offsets.assign(1, 0);
  out.face_vertices.clear();
  for (int f = 0; f < m.num_faces(); ++f) {
    const int b = m.face_offsets[static_cast<size_t>(f)], e = m.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b < 3) continue;
    out.face_vertices.insert(out.face_vertices.end(), m.face_vertices.begin() + b, m.face_vertices.begin() + e);
    out.face_offsets.push_back(static_cast<int>(out.face_vertices.size()));
  }
  return out;
}

}  // namespace

const std::vector<ExportFormat>& export_formats() {
  static const std::vector<ExportFormat> formats = [] {
    std::vector<ExportFormat> out;
    Assimp::Exporter exporter;
    for (size_t i = 0; i < exporter.GetExportFormatCount(); ++i) {
      const aiExportFormatDesc* d = exporter.GetExportFormatDescription(i);
      // pbrt segfaults in assimp 5.2.5 (measured on a single triangle); 3mf writes through its own zip
      // library, past the checked I/O: under a 4 KiB file-size limit it left a truncated 613-byte
      // archive and reported success.
      if (std::string(d->id) == "pbrt" || std::string(d->id) == "3mf") continue;
      out.push_back(describe(d->id, d->fileExtension, d->description));
    }
    // The own writers do not depend on assimp offering the format.
    for (const auto& [id, ext, text] : {std::array<const char*, 3>{"obj", "obj", ""}, {"objnomtl", "obj", ""},
                                        {"ply", "ply", ""}, {"plyb", "ply", ""}, {"gltf2", "gltf", ""}, {"glb2", "glb", ""}}) {
      bool listed = false;
      for (const auto& f : out) listed = listed || f.id == id;
      if (!listed) out.push_back(describe(id, ext, text));
    }
    return out;
  }();
  return formats;
}

bool is_export_format(const std::string& id) {
  for (const auto& f : export_formats())
    if (f.id == id) return true;
  return false;
}

const ExportFormat& export_format(const std::string& id) {
  for (const auto& f : export_formats())
    if (f.id == id) return f;
  throw std::invalid_argument("unknown mesh export format \"" + id + "\"");
}

fs::path export_meshes(const std::vector<PolyMesh>& meshes, const fs::path& directory, const std::string& stem,
                       const std::string& format_id, const ExportOptions& options) {
  const ExportFormat& format = export_format(format_id);
  check_stem(stem);
  for (size_t i = 0; i < meshes.size(); ++i) check_mesh(meshes[i], i);
  const std::string file_name = stem + "." + format.extension;

  // Triangulate first where asked or needed (the glTF writer does it itself).
  std::vector<PolyMesh> triangulated;
  const bool triangulate_here = (options.triangulate || format.needs_triangles) && format.id != "gltf2" && format.id != "glb2";
  // STL holds triangles only, and assimp's STL exporter wrote each particle as a facet of one vertex,
  // which no reader accepts: points and lines are left out there.
  const bool drop_points = format.id == "stl" || format.id == "stlb";
  if (triangulate_here) {
    triangulated.reserve(meshes.size());
    for (const PolyMesh& m : meshes) {
      PolyMesh t = triangulate(m).mesh;
      if (drop_points) t = without_points_and_lines(t);
      triangulated.push_back(std::move(t));
    }
  }
  const std::vector<PolyMesh>& out = triangulate_here ? triangulated : meshes;

  StagingDirectory staging(directory);
  // Errors name the final path: the staging directory is an implementation detail.
  const auto stage = [&](const std::string& name, const std::string& content) {
    write_file_durably(staging.path() / name, content, directory / name);
  };
  if (format.id == "obj" || format.id == "objnomtl") {
    ObjSettings settings;
    settings.significant_digits = options.double_precision ? 17 : 9;
    if (format.id == "obj") {
      settings.material_library = stem + ".mtl";
      stage(settings.material_library, obj_material_text());
    }
    stage(file_name, obj_text(out, settings));
  } else if (format.id == "ply" || format.id == "plyb") {
    stage(file_name, ply_bytes(out, PlySettings{format.id == "plyb", options.double_precision}));
  } else if (format.id == "gltf2") {
    const std::string bin_name = stem + ".bin";
    const GltfDocument doc = gltf_document(out, bin_name);
    if (!doc.binary.empty()) stage(bin_name, doc.binary);
    stage(file_name, doc.json);
  } else if (format.id == "glb2") {
    stage(file_name, glb_container(gltf_document(out, "")));
  } else {
    export_with_assimp(out, format.id, staging.path() / file_name, directory);
  }
  return staging.commit(file_name).back();
}

}  // namespace shellfrac::render_mesh
