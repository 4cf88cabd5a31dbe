// Strict reading of scene text: duplicate keys, numbers beyond a double, nesting, control
// characters in names, unique shell names, the degree the solver supports, the file size cap, and mesh
// files that cannot become a level set. Each case checks the JSON pointer and the reason.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "scene/mesh_import.hpp"
#include "scene/strict_json.hpp"

namespace shellfrac::scene {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// The error a scene text gets: its JSON pointer and message.
SceneError error_of(const std::string& text) {
  try {
    build(read_scene(text, "s.json"));
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text;
  return SceneError("", "", "");
}

std::string sheet(const std::string& shell_fields = "", const std::string& top = "") {
  return R"({)" + top + R"("shells": [{)" + shell_fields +
         R"("patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})";
}

TEST(StrictJson, DuplicateKeyNamesTheSecondWithLineAndColumn) {
  const std::string text = "{\"shells\": [{\"patch\": {\"type\": \"flat\", \"size\": [1, 1], \"cells\": [2, 2]},\n"
                           "  \"thickness\": 0.001, \"material\": {\"E\": 1e5, \"nu\": 0.7, \"nu\": 0.3, \"density\": 100}}]}";
  const SceneError e = error_of(text);
  EXPECT_EQ(e.json_path(), "/shells/0/material/nu");
  EXPECT_THAT(e.message(), HasSubstr("duplicate key \"nu\""));
  // The second "nu" starts in column 57 of line 2.
  EXPECT_THAT(e.message(), HasSubstr("line 2, column 57"));
  // Escapes are resolved before keys are compared: "\u006eu" is "nu".
  const SceneError escaped = error_of(sheet(R"("name": "a", "n\u0061me": "b", )"));
  EXPECT_EQ(escaped.json_path(), "/shells/0/name");
}

TEST(StrictJson, NumberBeyondADoubleIsRefusedWithItsPath) {
  const SceneError e = error_of(sheet("", "\"time\": {\"end\": 1e999},\n"));
  EXPECT_EQ(e.json_path(), "/time/end");
  EXPECT_THAT(e.message(), HasSubstr("1e999 is too large for a double"));
  EXPECT_THAT(e.message(), HasSubstr("line 1, column 18"));
  // Underflow is harmless (it reads as 0) and hits the range check instead.
  const SceneError tiny = error_of(sheet("", "\"time\": {\"frame_rate\": 1e-999},"));
  EXPECT_EQ(tiny.json_path(), "/time/frame_rate");
  EXPECT_THAT(tiny.message(), HasSubstr("out of range"));
}

TEST(StrictJson, DeepNestingAndSyntaxErrorsAreRefused) {
  std::string deep = "{\"name\": " + std::string(100, '[') + std::string(100, ']') + "}";
  const SceneError e = error_of(deep);
  EXPECT_THAT(e.message(), HasSubstr("nesting deeper than 64"));
  EXPECT_EQ(e.json_path().rfind("/name/0/0/0", 0), 0u) << e.json_path();
  const SceneError syntax = error_of("{\n  \"shells\": [1,,]\n}");
  EXPECT_THAT(syntax.message(), HasSubstr("invalid JSON at line 2, column 16"));
}

TEST(StrictJson, ControlCharactersInNamesAreRefused) {
  // Guards against injection: a newline would start new OBJ lines.
  const SceneError e = error_of(sheet(R"("name": "sheet\nv 9 9 9\nf 1 2 999999", )"));
  EXPECT_EQ(e.json_path(), "/shells/0/name");
  EXPECT_THAT(e.message(), HasSubstr("control character 0x0a at byte 5"));
  // A scene built in C++ gets the same check from the validator.
  Scene s = read_scene(sheet(), "c++");
  s.shells[0].name = std::string("tab\there");
  try {
    build(s);
    FAIL();
  } catch (const SceneError& err) {
    EXPECT_EQ(err.json_path(), "/shells/0/name");
    EXPECT_THAT(err.message(), HasSubstr("0x09"));
  }
  // Pins name shells too.
  const SceneError pin = error_of(sheet("", R"("pins": [{"shell": "a\u0007", "region": {}}],)"));
  EXPECT_EQ(pin.json_path(), "/pins/0/shell");
}

TEST(StrictJson, ShellNamesAreUnique) {
  const std::string shell = R"({"name": "cloth", "patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 100}})";
  const SceneError e = error_of("{\"shells\": [" + shell + ", " + shell + "]}");
  EXPECT_EQ(e.json_path(), "/shells/1/name");
  EXPECT_THAT(e.message(), HasSubstr("already used by /shells/0"));
  // An unnamed shell is "shell<index>", which an explicit name may not take.
  std::string named_shell1 = shell;
  named_shell1.replace(named_shell1.find("cloth"), 5, "shell1");
  std::string unnamed = shell;
  unnamed.erase(unnamed.find("\"name\": \"cloth\", "), 17);
  const SceneError implicit = error_of("{\"shells\": [" + named_shell1 + ", " + unnamed + "]}");
  EXPECT_EQ(implicit.json_path(), "/shells/1");
}

TEST(StrictJson, IndicesBeyondAnIntDoNotWrapAround) {
  // 4294967296 would wrap to control point 0 when narrowed to int.
  const SceneError e = error_of(sheet("", R"("pins": [{"shell": 0, "control_points": [[4294967296, 0]]}],)"));
  EXPECT_EQ(e.json_path(), "/pins/0/control_points/0/0");
  EXPECT_THAT(e.message(), HasSubstr("out of range"));
  EXPECT_EQ(error_of(sheet("", R"("pins": [{"shell": 4294967296, "region": {}}],)")).json_path(), "/pins/0/shell");
}

TEST(StrictJson, DegreeAboveTheSolverLimitIsARangeError) {
  const SceneError e = error_of(R"({"shells": [{"patch": {"type": "control_net", "degree": [8, 1],
      "knots_u": [0,0,0,0,0,0,0,0,0,1,1,1,1,1,1,1,1,1], "knots_v": [0, 0, 1, 1],
      "control_points": [[0,0,0]]}, "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})");
  EXPECT_EQ(e.json_path(), "/shells/0/patch/degree/0");
  EXPECT_THAT(e.message(), HasSubstr("[1, 7]"));
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-strict-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(StrictJson, SceneFileIsReadWithACap) {
  // /dev/zero never ends: the read stops one chunk past the cap.
  try {
    read_scene_file("/dev/zero", 1 << 20);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_THAT(e.message(), HasSubstr("larger than the limit of 1 MiB"));
  }
  const fs::path d = scratch("cap");
  try {
    read_scene_file(d.string());
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_THAT(e.message(), HasSubstr("is a directory"));
  }
  std::ofstream(d / "small.json") << "{}";
  EXPECT_EQ(read_scene_file((d / "small.json").string(), 2), "{}");
  EXPECT_THROW(read_scene_file((d / "small.json").string(), 1), SceneError);
  fs::remove_all(d);
}

// A mesh solid from OBJ text; the error of building it.
SceneError mesh_error(const std::string& obj) {
  const fs::path d = scratch("mesh");
  std::ofstream(d / "m.obj") << obj;
  std::ofstream(d / "s.json") << R"({"solids": [{"shape": "mesh", "file": "m.obj", "spacing": 0.1,
      "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})";
  try {
    load_model((d / "s.json").string());
  } catch (const SceneError& e) {
    fs::remove_all(d);
    return e;
  }
  fs::remove_all(d);
  ADD_FAILURE() << "accepted";
  return SceneError("", "", "");
}

const char* const kTetrahedron = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

TEST(MeshImport, OpenNonFiniteAndFlatMeshesAreRefusedByName) {
  const SceneError open = mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(open.json_path(), "/solids/0/file");
  EXPECT_THAT(open.message(), HasSubstr("m.obj"));
  EXPECT_THAT(open.message(), HasSubstr("not closed: 3 boundary edge(s)"));
  std::string nan = kTetrahedron;
  nan.replace(nan.find("v 0 0 1"), 7, "v 0 0 nan");
  EXPECT_THAT(mesh_error(nan).message(), HasSubstr("NaN or infinite"));
  // Two copies of one triangle, opposite windings: closed, but no volume.
  EXPECT_THAT(mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n").message(), HasSubstr("encloses no volume"));
}

TEST(MeshImport, StatsOfATetrahedron) {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const MeshStats s = mesh_stats(m);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_NEAR(s.volume, 1.0 / 6.0, 1e-15);  // outward winding: positive
  EXPECT_NEAR(s.area, 1.5 + std::sqrt(3.0) / 2.0, 1e-14);
  EXPECT_EQ(s.hi, Eigen::Vector3d(1, 1, 1));
}

TEST(MeshImport, VerticesSplitAlongAUvSeamDoNotOpenTheSurface) {
  // The tetrahedron with its last face on copies of its vertices (as a file with texture coordinates
  // stores a UV seam): still closed. Moving one copy by 1e-9 opens it: the moved face's two edges to
  // that copy, and the two edges the other faces had to the original (4 boundary edges).
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {4, 5, 6}};
  EXPECT_EQ(mesh_stats(m).boundary_edges, 0u);
  EXPECT_NEAR(mesh_stats(m).volume, 1.0 / 6.0, 1e-15);
  m.vertices[6] = {0, 0, 1 + 1e-9};
  EXPECT_EQ(mesh_stats(m).boundary_edges, 4u);
}

}  // namespace
}  // namespace shellfrac::scene
