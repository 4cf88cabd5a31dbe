// Meshes as users bring them, through the product: `shellfrac validate` refuses a brittle
// solid's closed but flipped or non-manifold mesh with exit code 2, the file, the JSON path and the
// counts, before any simulation; with "repair": true it validates with a warning saying what changed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "scene/json_io.hpp"
#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using shellfrac::test::Result;

Result shellfrac(const std::string& args) { return shellfrac::test::run_shellfrac(args); }

// OBJ of cubes of side 0.1 m at the given corners (8 vertices, 12 outward triangles each); `flip` lists
// triangles (numbered over the whole file) written in the opposite order.
std::string cubes_obj(const std::vector<std::array<double, 3>>& corners, const std::vector<int>& flip = {}) {
  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::ostringstream obj;
  int triangle = 0;
  for (size_t c = 0; c < corners.size(); ++c) {
    for (int k = 0; k < 8; ++k)
      obj << "v " << corners[c][0] + 0.1 * (k & 1) << " " << corners[c][1] + 0.1 * ((k >> 1) & 1) << " "
          << corners[c][2] + 0.1 * ((k >> 2) & 1) << "\n";
    const int base = 1 + 8 * static_cast<int>(c);
    for (const auto& q : quads)
      for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
        const bool flipped = std::find(flip.begin(), flip.end(), triangle++) != flip.end();
        obj << "f " << base + t[0] << " " << base + (flipped ? t[2] : t[1]) << " " << base + (flipped ? t[1] : t[2]) << "\n";
      }
  }
  return obj.str();
}

std::string mesh_scene(const std::string& file, const std::string& extra) {
  return R"({"gravity": [0, 0, 0], "solids": [{"name": "block", "spacing": 0.01,
    "material": {"E": 1e7, "nu": 0.2, "density": 1000, "failure_stress": 1e5, "fracture_energy": 100},
    "fracture": {"stop": {"max_steps": 5}}, "shape": "mesh", "file": ")" +
         file + "\"" + extra + "}]}";
}

TEST(MeshCheckCli, FlippedTriangleIsRefusedUnlessRepaired) {
  const fs::path d = shellfrac::test::scratch_folder("meshcheck", "flipped");
  std::ofstream(d / "flipped.obj") << cubes_obj({{0, 0, 0}}, {5});
  std::ofstream(d / "refused.json") << mesh_scene("flipped.obj", "");
  const Result refused = shellfrac("validate " + (d / "refused.json").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("/solids/0/file"));
  EXPECT_THAT(refused.output, HasSubstr((d / "flipped.obj").string()));
  EXPECT_THAT(refused.output, HasSubstr("mesh 'block' cannot be broken: it is not a closed manifold surface: 3 edges with inconsistent orientation"));
  EXPECT_THAT(refused.output, HasSubstr("; \"repair\": true can orient it"));
  EXPECT_THAT(refused.output, Not(HasSubstr(": OK")));

  std::ofstream(d / "repaired.json") << mesh_scene("flipped.obj", R"(, "repair": true)");
  const Result repaired = shellfrac("validate " + (d / "repaired.json").string());
  EXPECT_EQ(repaired.exit_code, 0) << repaired.output;
  EXPECT_THAT(repaired.output, HasSubstr("warning: " + (d / "flipped.obj").string() + ": mesh repaired (/solids/0/repair): 1 triangle reversed\n"));
  EXPECT_THAT(repaired.output, HasSubstr(": OK"));

  // The key reads and writes back.
  const shellfrac::scene::Scene s = shellfrac::scene::load_scene((d / "repaired.json").string());
  ASSERT_TRUE(s.solids[0].mesh.repair.has_value());
  EXPECT_TRUE(*s.solids[0].mesh.repair);
  EXPECT_EQ(shellfrac::scene::to_json(s)["solids"][0]["repair"], true);
  fs::remove_all(d);
}

TEST(MeshCheckCli, InsideOutCubeIsRefusedUnlessRepaired) {
  const fs::path d = shellfrac::test::scratch_folder("meshcheck", "inward");
  std::vector<int> all(12);
  for (int k = 0; k < 12; ++k) all[static_cast<size_t>(k)] = k;
  std::ofstream(d / "inward.obj") << cubes_obj({{0, 0, 0}}, all);
  std::ofstream(d / "refused.json") << mesh_scene("inward.obj", "");
  const Result refused = shellfrac("validate " + (d / "refused.json").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("/solids/0/file"));
  EXPECT_THAT(refused.output, HasSubstr("inside out (negative volume -0.001; flip the triangle order); \"repair\": true can orient it"));
  std::ofstream(d / "repaired.json") << mesh_scene("inward.obj", R"(, "repair": true)");
  const Result repaired = shellfrac("validate " + (d / "repaired.json").string());
  EXPECT_EQ(repaired.exit_code, 0) << repaired.output;
  EXPECT_THAT(repaired.output, HasSubstr("mesh repaired (/solids/0/repair): 12 triangles reversed\n"));
  fs::remove_all(d);
}

TEST(MeshCheckCli, CubesTouchingAtAVertexAreRefusedEvenWithRepair) {
  // This once passed validate and failed in the exact cutter after the MPM phase (exit 3).
  const fs::path d = shellfrac::test::scratch_folder("meshcheck", "touching");
  std::ofstream(d / "touching.obj") << cubes_obj({{0, 0, 0}, {0.1, 0.1, 0.1}});
  std::ofstream(d / "refused.json") << mesh_scene("touching.obj", "");
  const Result refused = shellfrac("validate " + (d / "refused.json").string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("/solids/0/file"));
  EXPECT_THAT(refused.output, HasSubstr((d / "touching.obj").string()));
  EXPECT_THAT(refused.output, HasSubstr(": it is not a closed manifold surface: 1 non-manifold vertex (where"));
  std::ofstream(d / "repaired.json") << mesh_scene("touching.obj", R"(, "repair": true)");
  const Result repaired = shellfrac("validate " + (d / "repaired.json").string());
  EXPECT_EQ(repaired.exit_code, 2) << repaired.output;
  EXPECT_THAT(repaired.output, HasSubstr("/solids/0/file"));
  // The OBJ gives the shared corner twice: merged, then split again by orienting the soup.
  EXPECT_THAT(repaired.output,
              HasSubstr("touching.obj (after repair: 1 coincident or unused vertex removed, 1 non-manifold vertex split): mesh 'block'"));
  EXPECT_THAT(refused.output, Not(HasSubstr("\"repair\": true can")));
  EXPECT_THAT(repaired.output, HasSubstr("1 non-manifold vertex (where"));
  fs::remove_all(d);
}

TEST(MeshCheckCli, RepairIsOnlyForBrittleSolids) {
  const fs::path d = shellfrac::test::scratch_folder("meshcheck", "plain");
  std::ofstream(d / "cube.obj") << cubes_obj({{0, 0, 0}});
  std::ofstream(d / "plain.json") << R"({"solids": [{"shape": "mesh", "file": "cube.obj", "repair": true, "spacing": 0.01,
    "material": {"E": 1e7, "nu": 0.2, "density": 1000}}]})";
  const Result r = shellfrac("validate " + (d / "plain.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("/solids/0/repair"));
  EXPECT_THAT(r.output, HasSubstr("\"repair\" is only for brittle solids"));
  fs::remove_all(d);
}

}  // namespace
