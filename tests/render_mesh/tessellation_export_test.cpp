#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "nurbs/patch_builders.hpp"
#include "render_mesh/exporter.hpp"
#include "render_mesh/surface_tessellation.hpp"

namespace shellfrac::render_mesh {
namespace {

namespace fs = std::filesystem;

TEST(Tessellation, VerticesNormalsAndUvsLieOnTheSurface) {
  const auto surf = nurbs::cylinder_segment(0.5, 2.0, 3.14159265358979, 6, 4);
  const PolyMesh m = tessellate(surf, 10, 7, "tube");
  ASSERT_EQ(m.num_vertices(), 11 * 8);
  ASSERT_EQ(m.num_faces(), 10 * 7);
  double worst_radius = 0, worst_normal = 0;
  for (int k = 0; k < m.num_vertices(); ++k) {
    const Vec3& p = m.positions[static_cast<size_t>(k)];
    // On a cylinder around axis_v (= y), the distance from the axis is the radius.
    worst_radius = std::max(worst_radius, std::abs(std::hypot(p.x(), p.z()) - 0.5));
    // Outward unit normal = radial direction.
    const Vec3 radial = Vec3(p.x(), 0, p.z()).normalized();
    worst_normal = std::max(worst_normal, (m.normals[static_cast<size_t>(k)] - radial).norm());
  }
  EXPECT_LE(worst_radius, 1e-14);
  EXPECT_LE(worst_normal, 1e-12);
  EXPECT_DOUBLE_EQ(m.uvs.front().x(), 0.0);
  EXPECT_DOUBLE_EQ(m.uvs.back().x(), 1.0);
  EXPECT_DOUBLE_EQ(m.uvs.back().y(), 1.0);
  // Faces wind counter-clockwise about the normal: the geometric face normal agrees with it.
  const int* f = &m.face_vertices[0];
  const Vec3 fn = (m.positions[f[1]] - m.positions[f[0]]).cross(m.positions[f[3]] - m.positions[f[0]]);
  EXPECT_GT(fn.dot(m.normals[f[0]]), 0.0);
}

TEST(Export, ObjRoundTripsVerticesAndFaces) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-export-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  const auto surf = nurbs::cylinder_segment(0.5, 1.0, 1.5, 4, 2);
  const PolyMesh m = tessellate(surf, 3, 2, "tube");
  const fs::path out = export_meshes({m}, d, "frame_00000", "obj");
  EXPECT_EQ(out, d / "frame_00000.obj");
  // shellfrac's OBJ writer keeps every vertex in order: v, vt and vn number k is vertex k - 1.
  std::ifstream in(out);
  std::string line;
  std::vector<Vec3> v, vn;
  std::vector<Vec2> vt;
  std::vector<std::vector<std::array<int, 3>>> faces;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    double a, b, c;
    if (tag == "v" && ls >> a >> b >> c) v.emplace_back(a, b, c);
    if (tag == "vn" && ls >> a >> b >> c) vn.emplace_back(a, b, c);
    if (tag == "vt" && ls >> a >> b) vt.emplace_back(a, b);
    if (tag == "f") {
      std::vector<std::array<int, 3>> f;
      std::string corner;
      while (ls >> corner) {
        std::array<int, 3> idx{};
        std::sscanf(corner.c_str(), "%d/%d/%d", &idx[0], &idx[1], &idx[2]);
        f.push_back(idx);
      }
      faces.push_back(f);
    }
  }
  ASSERT_EQ(faces.size(), 6u);
  EXPECT_EQ(v.size(), 12u);
  double pos_err = 0, normal_err = 0, uv_err = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    ASSERT_EQ(faces[f].size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      const auto mv = static_cast<size_t>(m.face_vertices[static_cast<size_t>(m.face_offsets[f]) + k]);
      const auto& idx = faces[f][k];
      EXPECT_EQ(idx, (std::array<int, 3>{static_cast<int>(mv) + 1, static_cast<int>(mv) + 1, static_cast<int>(mv) + 1}));
      pos_err = std::max(pos_err, (v[static_cast<size_t>(idx[0] - 1)] - m.positions[mv]).norm());
      uv_err = std::max(uv_err, (vt[static_cast<size_t>(idx[1] - 1)] - m.uvs[mv]).norm());
      normal_err = std::max(normal_err, (vn[static_cast<size_t>(idx[2] - 1)] - m.normals[mv]).norm());
    }
  }
  EXPECT_LE(pos_err, 5e-9);  // 9 significant digits
  EXPECT_LE(uv_err, 1e-9);
  EXPECT_LE(normal_err, 1e-9);
  // Nothing but the mesh and its material file remains (no staging directory).
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++files;
  EXPECT_EQ(files, 2);
  fs::remove_all(d);
}

TEST(Export, OtherAssimpFormatsAndUnknownFormat) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-export2-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  const PolyMesh m = tessellate(nurbs::flat_patch(1.0, 1.0, 2, 2), 2, 2, "sheet");
  ASSERT_TRUE(is_export_format("ply"));
  const fs::path ply = export_meshes({m}, d, "f", "ply");
  EXPECT_GT(fs::file_size(ply), 100u);
  EXPECT_THROW(export_meshes({m}, d, "g", "no-such-format"), std::invalid_argument);
  EXPECT_FALSE(fs::exists(d / "g.obj"));
  fs::remove_all(d);
}

}  // namespace
}  // namespace shellfrac::render_mesh
