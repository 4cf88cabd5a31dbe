// Stable export topology: every format keeps every PolyMesh vertex, in order, whatever the
// positions do; names cannot inject lines. Files are read back independently: our own OBJ
// parser, assimp's importers without aiProcess_JoinIdenticalVertices for PLY and glTF.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/exporter.hpp"
#include "render_mesh/object_name.hpp"
#include "render_mesh/obj_writer.hpp"

namespace shellfrac::render_mesh {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-topology-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct ObjFile {
  std::vector<Vec3> v, vn;
  std::vector<Vec2> vt;
  std::vector<std::vector<std::array<long, 3>>> faces;  // v/vt/vn per corner, 1-based (0 if absent)
  std::vector<std::string> objects, groups, tags;
  size_t points = 0;
};

ObjFile parse_obj(const fs::path& path) {
  ObjFile out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    out.tags.push_back(tag);
    double a, b, c;
    if (tag == "v" && ls >> a >> b >> c) out.v.emplace_back(a, b, c);
    if (tag == "vn" && ls >> a >> b >> c) out.vn.emplace_back(a, b, c);
    if (tag == "vt" && ls >> a >> b) out.vt.emplace_back(a, b);
    if (tag == "o") out.objects.push_back(line.substr(2));
    if (tag == "g") out.groups.push_back(line.substr(2));
    if (tag == "p") ++out.points;
    if (tag == "f") {
      std::vector<std::array<long, 3>> f;
      std::string corner;
      while (ls >> corner) {
        std::array<long, 3> idx{0, 0, 0};
        std::sscanf(corner.c_str(), "%ld/%ld/%ld", &idx[0], &idx[1], &idx[2]);
        f.push_back(idx);
      }
      out.faces.push_back(f);
    }
  }
  return out;
}

// A flat cracked sheet: a crack with a tip inside a quad, a branch and a crossing. With `closed` the
// shadow copies sit exactly on their crack vertex (a crack that has not opened yet: coincident vertices
// with equal normals and UVs 1e-5 apart, which assimp's glTF exporter merged); otherwise the part above
// the crack is lifted.
PolyMesh cracked_sheet(bool closed, const std::string& name, double x0 = 0.0) {
  CrackedTessellationSettings settings;
  settings.resolution_u = 10;
  settings.resolution_v = 8;
  const ParameterDomain domain;
  const std::vector<CrackSegment2> crack{{{0.0, 0.5}, {0.63, 0.51}}, {{0.63, 0.51}, {0.9, 0.77}},
                                         {{0.3, 0.2}, {0.35, 0.8}}};
  const ParameterMesh split = split_parameter_grid(domain, crack, settings);
  const ParameterMesh separated = separate_crack_vertices(split, settings.shadow_offset);
  std::vector<Vec3> positions;
  for (size_t k = 0; k < separated.uv.size(); ++k) {
    const Vec2 at = closed ? split.uv[static_cast<size_t>(separated.source_vertex[k])] : separated.uv[k];
    const double lift = closed ? 0.0 : (separated.uv[k].y() > 0.5 ? 0.01 : 0.0);
    positions.emplace_back(x0 + at.x(), at.y() + lift, 0.0);
  }
  return assemble_render_mesh(separated, domain, std::move(positions), {}, name);
}

PolyMesh particle_cloud() {
  PolyMesh cloud;
  cloud.name = "ball";
  for (int k = 0; k < 5; ++k) {
    cloud.positions.emplace_back(0.1 * k, -0.5, 0.2);
    cloud.add_face({k});
  }
  return cloud;
}

size_t coincident_pairs(const PolyMesh& m) {
  size_t pairs = 0;
  for (size_t i = 0; i < m.positions.size(); ++i)
    for (size_t j = i + 1; j < m.positions.size(); ++j) pairs += m.positions[i] == m.positions[j] ? 1 : 0;
  return pairs;
}

// Positions of an assimp import, mesh after mesh.
std::vector<Vec3> imported_positions(const aiScene* scene) {
  std::vector<Vec3> out;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i)
    for (unsigned k = 0; k < scene->mMeshes[i]->mNumVertices; ++k) {
      const aiVector3D& p = scene->mMeshes[i]->mVertices[k];
      out.emplace_back(p.x, p.y, p.z);
    }
  return out;
}

double largest_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0.0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) worst = std::max(worst, (a[k] - b[k]).norm());
  return worst;
}

size_t corners_to_triangles(const std::vector<PolyMesh>& meshes) {
  size_t n = 0;
  for (const PolyMesh& m : meshes)
    for (int f = 0; f < m.num_faces(); ++f) {
      const int size = m.face_offsets[f + 1] - m.face_offsets[f];
      n += size >= 3 ? static_cast<size_t>(size - 2) : 0;
    }
  return n;
}

TEST(ExportTopology, VertexCountAndOrderAreTheSameInEveryFormatAndFrame) {
  const fs::path d = fresh_dir("formats");
  const std::vector<PolyMesh> closed{cracked_sheet(true, "sheet"), cracked_sheet(true, "flap", 2.0), particle_cloud()};
  const std::vector<PolyMesh> opened{cracked_sheet(false, "sheet"), cracked_sheet(false, "flap", 2.0), particle_cloud()};
  ASSERT_GT(coincident_pairs(closed[0]), 20u);  // the case that changed the OBJ vertex count
  ASSERT_EQ(coincident_pairs(opened[0]), 0u);
  std::vector<Vec3> expected_closed, expected_opened;
  for (const auto& m : closed) expected_closed.insert(expected_closed.end(), m.positions.begin(), m.positions.end());
  for (const auto& m : opened) expected_opened.insert(expected_opened.end(), m.positions.begin(), m.positions.end());
  const size_t total = expected_closed.size();

  int frame = 0;
  for (const auto* meshes : {&closed, &opened}) {
    const std::vector<Vec3>& expected = meshes == &closed ? expected_closed : expected_opened;
    const std::string stem = "frame_" + std::to_string(frame++);
    SCOPED_TRACE(stem);
    // OBJ, read with our own parser: one v per vertex in order, faces as in the PolyMesh.
    const ObjFile obj = parse_obj(export_meshes(*meshes, d, stem, "obj"));
    ASSERT_EQ(obj.v.size(), total);
    EXPECT_EQ(obj.vt.size(), total - 5);  // the particles have no UVs
    EXPECT_EQ(obj.vn.size(), total - 5);
    EXPECT_LE(largest_difference(obj.v, expected), 5e-9);  // 9 significant digits on coordinates <= 3
    EXPECT_EQ(obj.objects, (std::vector<std::string>{"sheet", "flap", "ball"}));
    EXPECT_EQ(obj.groups, obj.objects);
    EXPECT_EQ(obj.points, 5u);
    size_t faces = 0;
    long base = 0;
    for (const auto& m : *meshes) {
      for (int f = 0; f < m.num_faces() && m.face_offsets[f + 1] - m.face_offsets[f] >= 3; ++f, ++faces) {
        const auto& corners = obj.faces.at(faces);
        ASSERT_EQ(corners.size(), static_cast<size_t>(m.face_offsets[f + 1] - m.face_offsets[f]));
        for (size_t k = 0; k < corners.size(); ++k) {
          const long v = base + m.face_vertices[static_cast<size_t>(m.face_offsets[f]) + k] + 1;
          EXPECT_EQ(corners[k], (std::array<long, 3>{v, v, v}));
        }
      }
      base += m.num_vertices();
    }
    EXPECT_EQ(faces, obj.faces.size());

    // PLY (assimp's exporter, ASCII and binary), read back by assimp without joining vertices.
    for (const char* format : {"ply", "plyb"}) {
      Assimp::Importer importer;
      const aiScene* s = importer.ReadFile(export_meshes(*meshes, d, stem + format, format).string(), 0);
      ASSERT_NE(s, nullptr) << importer.GetErrorString();
      const auto positions = imported_positions(s);
      EXPECT_EQ(positions.size(), total) << format;
      EXPECT_LE(largest_difference(positions, expected), 1e-6) << format;  // single precision
    }
    // assimp formats flagged keeps_vertices: read back in order (x3d triangulated).
    for (const char* format : {"assbin", "x3d"}) {
      ASSERT_TRUE(export_format(format).keeps_vertices);
      Assimp::Importer importer;
      const aiScene* s = importer.ReadFile(export_meshes(*meshes, d, stem + format, format).string(), 0);
      ASSERT_NE(s, nullptr) << importer.GetErrorString();
      const auto positions = imported_positions(s);
      EXPECT_EQ(positions.size(), total) << format;
      EXPECT_LE(largest_difference(positions, expected), 1e-6) << format;
    }
    // glTF 2 (our writer), text and binary, read back by assimp: one mesh per PolyMesh, every vertex.
    for (const char* format : {"gltf2", "glb2"}) {
      Assimp::Importer importer;
      const aiScene* s = importer.ReadFile(export_meshes(*meshes, d, stem + format, format).string(), 0);
      ASSERT_NE(s, nullptr) << importer.GetErrorString();
      ASSERT_EQ(s->mNumMeshes, 3u) << format;
      size_t triangles = 0;
      for (unsigned i = 0; i < 3; ++i) {
        EXPECT_EQ(s->mMeshes[i]->mNumVertices, static_cast<unsigned>((*meshes)[i].num_vertices())) << format;
        EXPECT_EQ(std::string(s->mMeshes[i]->mName.C_Str()), (*meshes)[i].name);
        for (unsigned f = 0; f < s->mMeshes[i]->mNumFaces; ++f) triangles += s->mMeshes[i]->mFaces[f].mNumIndices == 3 ? 1 : 0;
      }
      EXPECT_EQ(triangles, corners_to_triangles(*meshes)) << format;
      EXPECT_LE(largest_difference(imported_positions(s), expected), 1e-6) << format;
      // UVs come back as written (the writer stores t = 1 - v, the importer flips it back).
      double uv_error = 0.0;
      for (unsigned k = 0; k < s->mMeshes[0]->mNumVertices; ++k)
        uv_error = std::max(uv_error, (Vec2(s->mMeshes[0]->mTextureCoords[0][k].x, s->mMeshes[0]->mTextureCoords[0][k].y) -
                                       (*meshes)[0].uvs[k]).norm());
      EXPECT_LE(uv_error, 1e-6) << format;
    }
  }
  // Nothing but complete frames is left: obj + mtl, 2 ply, assbin, x3d, gltf + bin, glb per frame.
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) {
    EXPECT_EQ(e.path().filename().string().rfind(".staging", 0), std::string::npos);
    ++files;
  }
  EXPECT_EQ(files, 2 * 9);
  fs::remove_all(d);
}

TEST(ExportTopology, AssimpReadsOurObjAndTriangulatesNothingItself) {
  const fs::path d = fresh_dir("obj-assimp");
  const std::vector<PolyMesh> meshes{cracked_sheet(false, "sheet")};
  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile(export_meshes(meshes, d, "f", "obj").string(), 0);
  ASSERT_NE(s, nullptr) << importer.GetErrorString();
  unsigned faces = 0, corners = 0;
  for (unsigned i = 0; i < s->mNumMeshes; ++i)
    for (unsigned f = 0; f < s->mMeshes[i]->mNumFaces; ++f, ++faces) corners += s->mMeshes[i]->mFaces[f].mNumIndices;
  EXPECT_EQ(faces, static_cast<unsigned>(meshes[0].num_faces()));
  EXPECT_EQ(corners, static_cast<unsigned>(meshes[0].face_vertices.size()));
  fs::remove_all(d);
}

TEST(ExportTopology, TriangulateOptionKeepsVertices) {
  const fs::path d = fresh_dir("triangulate");
  const std::vector<PolyMesh> meshes{cracked_sheet(false, "sheet"), particle_cloud()};
  ExportOptions options;
  options.triangulate = true;
  const ObjFile obj = parse_obj(export_meshes(meshes, d, "t", "obj", options));
  EXPECT_EQ(obj.v.size(), static_cast<size_t>(meshes[0].num_vertices() + 5));
  EXPECT_EQ(obj.faces.size(), corners_to_triangles(meshes));
  for (const auto& f : obj.faces) EXPECT_EQ(f.size(), 3u);
  EXPECT_EQ(obj.points, 5u);
  // stl takes triangles only: triangulated without being asked (n - 2 facets per polygon), and the
  // particles, which STL cannot hold, are left out (assimp wrote them as one-vertex facets).
  const std::string stl = slurp(export_meshes(meshes, d, "s", "stl"));
  size_t facets = 0;
  for (size_t at = stl.find("endfacet"); at != std::string::npos; at = stl.find("endfacet", at + 1)) ++facets;
  EXPECT_EQ(facets, corners_to_triangles({meshes[0]}));
  fs::remove_all(d);
}

TEST(ExportTopology, DoublePrecisionRestoresEveryCoordinate) {
  const fs::path d = fresh_dir("precision");
  PolyMesh m;
  m.name = "p";
  m.positions = {{0.1 + 1e-12, 1.0 / 3.0, -2.0 / 7.0}, {12345.678901234567, 1e-300, 0.0}, {std::sqrt(2.0), 0.0, 1.0}};
  m.add_face({0, 1, 2});
  ExportOptions options;
  options.double_precision = true;
  const ObjFile exact = parse_obj(export_meshes({m}, d, "double", "obj", options));
  ASSERT_EQ(exact.v.size(), 3u);
  for (size_t k = 0; k < 3; ++k) EXPECT_EQ(exact.v[k], m.positions[k]) << k;  // bit for bit
  const ObjFile rounded = parse_obj(export_meshes({m}, d, "float", "obj"));
  ASSERT_EQ(rounded.v.size(), 3u);
  EXPECT_NE(rounded.v[0].x(), m.positions[0].x());
  for (size_t k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(rounded.v[k][c] - m.positions[k][c]), 5e-9 * std::abs(m.positions[k][c]));
  EXPECT_TRUE(export_format("obj").double_precision);
  EXPECT_TRUE(export_format("plyb").double_precision);
  EXPECT_FALSE(export_format("stl").double_precision);
  fs::remove_all(d);
}

TEST(ExportNames, ControlCharactersNewlinesAndBadUtf8AreReplaced) {
  EXPECT_EQ(export_object_name("sheet", "x"), "sheet");
  EXPECT_EQ(export_object_name("sheet\nv 9 9 9\nf 1 2 999999", "x"), "sheet_v_9_9_9_f_1_2_999999");
  EXPECT_EQ(export_object_name("a\rb\tc\x01" "d\x7f", "x"), "a_b_c_d_");
  EXPECT_EQ(export_object_name("Tuch \xc3\xa4 #1", "x"), "Tuch_\xc3\xa4__1");         // UTF-8 letters kept
  EXPECT_EQ(export_object_name("a\xe2\x80\xa8" "b\xc2\x85" "c", "x"), "a_b_c");      // U+2028, NEL
  EXPECT_EQ(export_object_name("bad\xff\xc3", "x"), "bad__");                         // invalid UTF-8
  EXPECT_EQ(export_object_name("\xed\xa0\x80", "x"), "___");                          // a surrogate
  EXPECT_EQ(export_object_name("", "shell0"), "shell0");
  EXPECT_EQ(export_object_name(std::string(400, 'a'), "x").size(), 255u);
  EXPECT_EQ(export_object_name(std::string(254, 'a') + "\xc3\xa4", "x").size(), 254u);  // cut at a code point
}

TEST(ExportNames, AHostileNameCannotInjectLines) {
  const fs::path d = fresh_dir("names");
  PolyMesh m = cracked_sheet(false, "sheet\nv 9 9 9\nf 1 2 999999\r\n# \xe2\x80\xa8v 1 1 1");
  const ObjFile obj = parse_obj(export_meshes({m}, d, "f", "obj"));
  EXPECT_EQ(obj.v.size(), static_cast<size_t>(m.num_vertices()));
  EXPECT_EQ(obj.faces.size(), static_cast<size_t>(m.num_faces()));
  ASSERT_EQ(obj.objects.size(), 1u);
  EXPECT_EQ(obj.objects[0], "sheet_v_9_9_9_f_1_2_999999_____v_1_1_1");
  for (const std::string& tag : obj.tags)
    EXPECT_TRUE(tag == "#" || tag == "mtllib" || tag == "o" || tag == "g" || tag == "usemtl" || tag == "v" ||
                tag == "vt" || tag == "vn" || tag == "f")
        << tag;
  for (const auto& f : obj.faces)
    for (const auto& c : f) EXPECT_LE(c[0], static_cast<long>(obj.v.size()));
  // glTF (JSON) and an assimp format (COLLADA, XML) carry the same sanitised name and no raw newline.
  Assimp::Importer importer;
  const aiScene* s = importer.ReadFile(export_meshes({m}, d, "f", "glb2").string(), 0);
  ASSERT_NE(s, nullptr) << importer.GetErrorString();
  EXPECT_EQ(std::string(s->mMeshes[0]->mName.C_Str()), obj.objects[0]);
  const std::string dae = slurp(export_meshes({m}, d, "f", "collada"));
  EXPECT_EQ(dae.find("sheet\n"), std::string::npos);
  EXPECT_NE(dae.find(obj.objects[0]), std::string::npos);
  fs::remove_all(d);
}

TEST(ExportFormats, PropertiesAndBadArguments) {
  EXPECT_TRUE(export_format("obj").own_writer);
  EXPECT_TRUE(export_format("glb2").needs_triangles);
  EXPECT_TRUE(export_format("ply").keeps_vertices);
  EXPECT_FALSE(export_format("gltf").keeps_vertices);  // glTF 1 through assimp: joins vertices
  EXPECT_FALSE(export_format("stl").keeps_vertices);
  EXPECT_FALSE(is_export_format("pbrt"));              // assimp 5.2's exporter crashes
  EXPECT_FALSE(is_export_format("3mf"));               // writes past the checked I/O
  const fs::path d = fresh_dir("bad");
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 3});
  EXPECT_THROW(export_meshes({m}, d, "f", "obj"), std::invalid_argument);  // index outside the vertices
  m.face_vertices.back() = 2;
  EXPECT_THROW(export_meshes({m}, d, "a/b", "obj"), std::invalid_argument);
  EXPECT_THROW(export_meshes({m}, d, "a\nb", "obj"), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
}

}  // namespace
}  // namespace shellfrac::render_mesh
