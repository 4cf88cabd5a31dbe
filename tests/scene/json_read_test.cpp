// The scene document: JSON reading (types, unknown keys), writing back, and the validation of scenes
// built in C++, which must refuse exactly what the reader refuses.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/range.hpp"
#include "scene/scene_error.hpp"
#include "scene/validate.hpp"

namespace shellfrac::scene {
namespace {

using ::testing::HasSubstr;
using Json = nlohmann::json;

TEST(Range, BoundsAndWording) {
  EXPECT_TRUE(Range::positive().contains(1e-300));
  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::non_negative().contains(0.0));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(0.5));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(-1));
  EXPECT_TRUE(Range::open(-1, 0.5).contains(0.4999));
  EXPECT_TRUE(Range::left_open(0, 1).contains(1.0));
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(Range::positive().describe(), "> 0");
  EXPECT_EQ(Range::open(-1, 0.5).describe(), "in (-1, 0.5)");
  EXPECT_EQ(Range::closed(1, 10).describe(), "in [1, 10]");
}

const char* kSheet = R"({"name": "sheet", "patch": {"type": "flat", "size": [1, 1], "cells": [4, 4]},
                         "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}})";

SceneError refusal(const std::string& text) {
  try {
    read_scene(text, "f.json");
  } catch (const SceneError& e) {
    return e;
  }
  throw std::runtime_error("the document was accepted: " + text);
}

TEST(SceneJson, UnknownKeyListsAllowedKeys) {
  const SceneError e = refusal(std::string(R"({"shells": [)") + kSheet + R"(], "grdi": {"dx": 0.1}})");
  EXPECT_EQ(e.json_path(), "/grdi");
  EXPECT_THAT(e.message(), HasSubstr("unknown key \"grdi\": allowed here are colliders, cracks, damping, gravity, grid, interfaces, loads, name, "
                                      "output, pins, quality, rigid, shells, solids, time, verify"));
}

TEST(SceneJson, TypeErrorsNameTheFoundType) {
  EXPECT_THAT(refusal(R"({"damping": "1"})").message(), HasSubstr("expected a number, got string"));
  const SceneError integer = refusal(std::string(R"({"shells": [)") + kSheet + R"(], "cracks": {"extraction_interval": 1.5}})");
  EXPECT_EQ(integer.json_path(), "/cracks/extraction_interval");
  EXPECT_THAT(integer.message(), HasSubstr("expected an integer, got number 1.5"));
  EXPECT_EQ(refusal(R"({"gravity": [0, "x", 0]})").json_path(), "/gravity/1");
}

TEST(SceneJson, NonObjectIsRejected) {
  const SceneError e = refusal("[1, 2]");
  EXPECT_EQ(e.json_path(), "/");
  EXPECT_THAT(e.message(), HasSubstr("expected an object, got array"));
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A scene written back is the document it was read from: every key the file has, none it has not.
TEST(SceneJson, EveryShippedSceneRoundTrips) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SHELLFRAC_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    const std::string text = read_file(entry.path());
    const Json written = to_json(read_scene(text, entry.path().string()));
    EXPECT_EQ(written, Json::parse(text)) << entry.path();
    ++scenes;
  }
  EXPECT_GE(scenes, 20);
}

Scene sheet_in_code() {
  Scene s;
  s.source = "code";
  Shell sheet;
  sheet.name = "sheet";
  sheet.patch = Patch::flat({1.0, 1.0}, {4, 4});
  sheet.thickness = 0.001;
  Material m;
  m.youngs_modulus = 1e5;
  m.poisson_ratio = 0.3;
  m.density = 200;
  sheet.material = m;
  s.shells.push_back(sheet);
  return s;
}

SceneError refusal(const Scene& s) {
  try {
    build(s);
  } catch (const SceneError& e) {
    return e;
  }
  throw std::runtime_error("the scene was accepted");
}

// A scene built in C++ gets the reader's checks with the same JSON pointers and words.
TEST(SceneValues, RefusedLikeTheFile) {
  EXPECT_NO_THROW(build(sheet_in_code()));
  Scene s = sheet_in_code();
  s.shells[0].material->poisson_ratio = 0.7;
  SceneError e = refusal(s);
  EXPECT_EQ(e.file(), "code");
  EXPECT_EQ(e.json_path(), "/shells/0/material/nu");
  EXPECT_EQ(e.message(), "value 0.7 is out of range: must be in (-1, 0.5)");

  s = sheet_in_code();
  s.shells[0].thickness.reset();
  e = refusal(s);
  EXPECT_EQ(e.json_path(), "/shells/0/thickness");
  EXPECT_EQ(e.message(), "required key is missing");

  s = sheet_in_code();
  s.shells[0].cuts.push_back({std::vector<Vec2>{{0.1, 0.5}}, std::nullopt});
  e = refusal(s);
  EXPECT_EQ(e.json_path(), "/shells/0/cuts/0/points");
  EXPECT_EQ(e.message(), "expected at least 2 points [u, v], got 1");

  s = sheet_in_code();
  s.shells[0].patch->cells = Int2{0, 4};
  EXPECT_EQ(refusal(s).json_path(), "/shells/0/patch/cells/0");

  s = sheet_in_code();
  s.grid.transfer = "polypic";  // not "flip": a valid transfer
  e = refusal(s);
  EXPECT_EQ(e.json_path(), "/grid/transfer");
  EXPECT_EQ(e.message(), "unknown value \"polypic\": allowed are \"adaptive\", \"pic\", \"apic\", \"flip\", \"aflip\"");

  s = sheet_in_code();
  Pin pin;
  pin.shell = std::string("cloth");
  pin.region = PinRegion{};
  s.pins.push_back(pin);
  e = refusal(s);
  EXPECT_EQ(e.json_path(), "/pins/0/shell");
  EXPECT_EQ(e.message(), "no shell is named \"cloth\"");

  s = sheet_in_code();
  s.shells[0].patch->axis_v = Vec3{1, 0, 0};
  EXPECT_THAT(refusal(s).message(), HasSubstr("axis_v must be orthogonal to axis_u"));
}

// The same scene as a document and as values gives the same solver inputs.
TEST(SceneValues, BuildLikeTheDocumentTheyWriteTo) {
  Scene s = sheet_in_code();
  s.shells[0].cuts.push_back({std::vector<Vec2>{{0.0, 0.5}, {0.4, 0.5}}, std::nullopt});
  s.time.end = 0.25;
  const Model direct = build(s);
  const Model via_json = build_model(to_json(s).dump(), "code");
  EXPECT_EQ(direct.shells[0].surface.control_points(), via_json.shells[0].surface.control_points());
  EXPECT_EQ(direct.shells[0].cuts[0].points, via_json.shells[0].cuts[0].points);
  EXPECT_EQ(direct.time.end, 0.25);
  EXPECT_EQ(via_json.time.end, 0.25);
  EXPECT_EQ(to_json(read_scene(to_json(s), "code")), to_json(s));
}

}  // namespace
}  // namespace shellfrac::scene
