// Every scene validation rule: feed one bad value into an otherwise valid scene and check that the
// error names the JSON path of the value and says what is allowed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::scene {
using sim::Simulation;
namespace {

using ::testing::HasSubstr;
using Json = nlohmann::json;

Json valid_scene() {
  return Json::parse(R"({
    "name": "t",
    "time": {"end": 0.1, "frame_rate": 30, "cfl": 0.5},
    "output": {"format": "obj", "resolution": [4, 4]},
    "shells": [
      {"name": "a", "patch": {"type": "flat", "size": [1, 2], "cells": [4, 8]},
       "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}},
      {"name": "b", "patch": {"type": "control_net", "degree": [2, 1],
         "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 1, 1],
         "control_points": [[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,1],[2,1,0]],
         "weights": [1, 0.5, 1, 1, 0.5, 1]},
       "thickness": 0.002, "material": {"E": 1e6, "nu": 0.2, "density": 500}},
      {"name": "c", "patch": {"type": "cone", "radius_bottom": 1, "radius_top": 0.5, "height": 1,
         "sweep_degrees": 90, "cells": [4, 2]},
       "thickness": 0.002, "material": {"E": 1e6, "nu": 0.2, "density": 500}}
    ]})");
}

struct BadCase {
  const char* label;
  const char* pointer;     // JSON pointer of the value to replace (or of a new key)
  const char* value;       // JSON text of the replacement; "DELETE" removes the key
  const char* error_path;  // path the error must name
  const char* message;     // substring the message must contain
};

std::ostream& operator<<(std::ostream& os, const BadCase& c) { return os << c.label; }

class SceneValidation : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneValidation, RejectsWithPathAndReason) {
  const BadCase& c = GetParam();
  Json j = valid_scene();
  const Json::json_pointer ptr(c.pointer);
  if (std::string(c.value) == "DELETE")
    j[ptr.parent_pointer()].erase(ptr.back());
  else
    j[ptr] = Json::parse(c.value);
  try {
    build_model(j.dump(), "bad.json");
    FAIL() << "scene was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "bad.json");
    EXPECT_EQ(e.json_path(), c.error_path) << e.what();
    EXPECT_THAT(e.message(), HasSubstr(c.message)) << e.what();
    EXPECT_THAT(std::string(e.what()), HasSubstr(std::string("bad.json: ") + c.error_path));
  }
}

const BadCase kBadCases[] = {
    {"flat_degree_one", "/shells/0/patch/degree", "[1, 2]", "/shells/0/patch/degree/0", "out of range"},
    {"cone_degree_eight", "/shells/2/patch/degree", "[3, 8]", "/shells/2/patch/degree/1", "out of range"},
    {"elevate_past_seven", "/shells/1/patch/elevate", "[6, 0]", "/shells/1/patch/elevate",
     "degree + elevate must stay at most 7"},
    {"elevate_negative", "/shells/1/patch/elevate", "[-1, 0]", "/shells/1/patch/elevate/0", "out of range"},
    {"elevate_on_flat", "/shells/0/patch/elevate", "[1, 1]", "/shells/0/patch/elevate", "unknown key"},
    {"negative_thickness", "/shells/0/thickness", "-0.001", "/shells/0/thickness", "must be > 0"},
    {"zero_thickness", "/shells/0/thickness", "0", "/shells/0/thickness", "must be > 0"},
    {"thickness_as_string", "/shells/0/thickness", "\"thin\"", "/shells/0/thickness", "expected a number, got string"},
    {"missing_thickness", "/shells/0/thickness", "DELETE", "/shells/0/thickness", "required key is missing"},
    {"poisson_half", "/shells/0/material/nu", "0.5", "/shells/0/material/nu", "in (-1, 0.5)"},
    {"poisson_minus_one", "/shells/0/material/nu", "-1", "/shells/0/material/nu", "in (-1, 0.5)"},
    {"negative_E", "/shells/0/material/E", "-3", "/shells/0/material/E", "must be > 0"},
    {"zero_density", "/shells/1/material/density", "0", "/shells/1/material/density", "must be > 0"},
    {"unknown_material_model", "/shells/0/material/model", "\"rubbery\"", "/shells/0/material/model", "allowed are \"neo_hookean\""},
    {"unknown_material_key", "/shells/0/material/Young", "1", "/shells/0/material/Young", "unknown key"},
    {"unknown_top_level_key", "/colour", "\"red\"", "/colour", "allowed here are"},
    {"unknown_patch_type", "/shells/0/patch/type", "\"sphere\"", "/shells/0/patch/type", "allowed are \"flat\""},
    {"flat_zero_cells", "/shells/0/patch/cells", "[0, 4]", "/shells/0/patch/cells/0", "in [1, 10000]"},
    {"flat_fractional_cells", "/shells/0/patch/cells", "[2.5, 4]", "/shells/0/patch/cells/0", "expected an integer"},
    {"flat_size_wrong_length", "/shells/0/patch/size", "[1]", "/shells/0/patch/size", "array of 2 numbers"},
    {"flat_negative_size", "/shells/0/patch/size", "[1, -2]", "/shells/0/patch/size/1", "must be > 0"},
    {"flat_axes_not_orthogonal", "/shells/0/patch/axis_v", "[1, 1, 0]", "/shells/0/patch/axis_v", "orthogonal"},
    {"flat_zero_axis", "/shells/0/patch/axis_u", "[0, 0, 0]", "/shells/0/patch/axis_u", "non-zero"},
    {"flat_unknown_key", "/shells/0/patch/radius", "1", "/shells/0/patch/radius", "unknown key"},
    {"knots_not_monotone", "/shells/1/patch/knots_u", "[0, 0, 0.5, 0.2, 1, 1]", "/shells/1/patch/knots_u", "non-decreasing"},
    {"knots_too_few", "/shells/1/patch/knots_v", "[0, 1]", "/shells/1/patch/knots_v", "knots"},
    {"knots_not_finite", "/shells/1/patch/knots_u", "[0, 0, 0, 1, 1, \"x\"]", "/shells/1/patch/knots_u/5", "expected a number"},
    {"net_size_mismatch", "/shells/1/patch/control_points", "[[0,0,0],[1,0,0],[2,0,0],[0,1,0]]", "/shells/1/patch/control_points", "require 3 x 2 = 6"},
    {"net_point_not_3d", "/shells/1/patch/control_points/4", "[1, 1]", "/shells/1/patch/control_points/4", "[x, y, z]"},
    {"net_negative_weight", "/shells/1/patch/weights/3", "-1", "/shells/1/patch/weights/3", "must be > 0"},
    {"net_weight_count", "/shells/1/patch/weights", "[1, 1, 1]", "/shells/1/patch/weights", "one weight per control point"},
    {"net_degree_zero", "/shells/1/patch/degree", "[0, 1]", "/shells/1/patch/degree/0", "in [1, 7]"},
    {"cone_both_radii_zero", "/shells/2/patch",
     R"({"type": "cone", "radius_bottom": 0, "radius_top": 0, "height": 1, "cells": [4, 2]})",
     "/shells/2/patch/radius_top", "at least one radius"},
    {"cone_sweep_too_large", "/shells/2/patch/sweep_degrees", "400", "/shells/2/patch/sweep_degrees", "in (0, 360]"},
    {"cone_negative_height", "/shells/2/patch/height", "-1", "/shells/2/patch/height", "must be > 0"},
    {"shells_empty", "/shells", "[]", "/shells", "at least one shell or solid"},
    {"shells_missing", "/shells", "DELETE", "/shells", "at least one shell or solid"},
    {"solid_unknown_shape", "/solids", R"([{"shape": "torus", "center": [0, 0, 0], "spacing": 0.1,
       "material": {"E": 1, "nu": 0.3, "density": 1}}])", "/solids/0/shape", "allowed are \"sphere\", \"box\""},
    {"solid_spacing_too_large", "/solids", R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 0.1,
       "spacing": 0.5, "material": {"E": 1, "nu": 0.3, "density": 1}}])", "/solids/0/spacing", "no particle would fit"},
    {"solid_mesh_missing_file", "/solids", R"([{"shape": "mesh", "file": "no/such/mesh.obj", "spacing": 0.05,
       "material": {"E": 1, "nu": 0.3, "density": 1}}])", "/solids/0/file", "cannot import mesh"},
    {"collider_mesh_missing_voxel", "/colliders", R"([{"shape": "mesh", "file": "x.obj"}])",
     "/colliders/0/voxel_size", "required key is missing"},
    {"collider_without_geometry", "/colliders", R"([{"shape": "sphere", "center": [0, 0, 0]}])",
     "/colliders/0/radius", "required key is missing"},
    {"pin_outside_patch", "/pins", R"([{"shell": 0, "control_points": [[6, 0]]}])", "/pins/0/control_points/0",
     "outside the patch"},
    {"pin_unknown_shell", "/pins", R"([{"shell": "nope", "region": {"u": [0, 0.1]}}])", "/pins/0/shell",
     "no shell is named"},
    {"pin_empty_region", "/pins", R"([{"shell": 0, "region": {"u": [0.01, 0.02], "v": [0.01, 0.02]}}])",
     "/pins/0/region", "selects no control point"},
    {"keyframes_not_increasing", "/colliders", R"([{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
       "motion": {"keyframes": [{"time": 1}, {"time": 0.5}]}}])", "/colliders/0/motion/keyframes/1/time",
     "increase strictly"},
    {"plasticity_zero_yield", "/shells/0/material/plasticity", R"({"yield_stress": 0})",
     "/shells/0/material/plasticity/yield_stress", "must be > 0"},
    {"unsafe_dt_needs_dt", "/time/enforce_stability_bound", "false", "/time/enforce_stability_bound",
     "needs an explicit"},
    {"shell_not_object", "/shells/0", "3", "/shells/0", "expected an object"},
    {"time_negative_rate", "/time/frame_rate", "-24", "/time/frame_rate", "must be > 0"},
    {"time_cfl_above_one", "/time/cfl", "1.5", "/time/cfl", "in (0, 1]"},
    {"time_zero_dt", "/time/dt", "0", "/time/dt", "must be > 0"},
    {"time_substep_not_bool", "/time/allow_substepping", "\"yes\"", "/time/allow_substepping", "true or false"},
    {"output_unknown_format", "/output/format", "\"docx\"", "/output/format", "unknown mesh format"},
    {"output_zero_resolution", "/output/resolution", "[0, 4]", "/output/resolution/0", "in [1, 4096]"},
    // Fracture material (thesis sec. 4.4.1, Eq. 2.28).
    {"fracture_zero_failure_stress", "/shells/0/material/fracture", R"({"failure_stress": 0, "fracture_energy": 100})",
     "/shells/0/material/fracture/failure_stress", "must be > 0"},
    {"fracture_negative_energy", "/shells/0/material/fracture", R"({"failure_stress": 1e4, "fracture_energy": -5})",
     "/shells/0/material/fracture/fracture_energy", "must be > 0"},
    {"fracture_missing_energy", "/shells/0/material/fracture", R"({"failure_stress": 1e4})",
     "/shells/0/material/fracture/fracture_energy", "required key is missing"},
    {"fracture_unknown_damage_rule", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100, "damage_rule": "permanent"})",
     "/shells/0/material/fracture/damage_rule", "unknown value \"permanent\": allowed are \"healing\", \"monotone\""},
    {"fracture_residual_too_large", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100, "residual_stiffness": 0.5})",
     "/shells/0/material/fracture/residual_stiffness", "in [0, 0.1]"},
    {"fracture_weibull_zero_modulus", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100, "weibull": {"modulus": 0}})",
     "/shells/0/material/fracture/weibull/modulus", "must be > 0"},
    {"fracture_weibull_negative_seed", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100, "weibull": {"modulus": 10, "seed": -1}})",
     "/shells/0/material/fracture/weibull/seed", "in [0, 2147483647]"},
    {"fracture_region_two_points", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100,
         "regions": [{"polygon": [[0, 0], [1, 0]], "failure_stress": 1e5}]})",
     "/shells/0/material/fracture/regions/0/polygon", "expected at least 3 points [u, v], got 2"},
    {"fracture_region_malformed_point", "/shells/0/material/fracture",
     R"({"failure_stress": 1e4, "fracture_energy": 100,
         "regions": [{"polygon": [[0, 0], [1, 0], [1]], "failure_stress": 1e5}]})",
     "/shells/0/material/fracture/regions/0/polygon/2", "expected a parameter point [u, v] of two finite numbers"},
    // Prescribed cuts, in the patch's parameter coordinates (shell 0 has the domain [0, 1] x [0, 1]).
    {"cut_outside_domain", "/shells/0/cuts", R"([{"points": [[0.5, 0.5], [1.5, 0.5]]}])", "/shells/0/cuts/0/points",
     "vertex 1 (1.5, 0.5) lies outside the domain"},
    {"cut_zero_length_segment", "/shells/0/cuts", R"([{"points": [[0.2, 0.5], [0.6, 0.5], [0.6, 0.5]]}])",
     "/shells/0/cuts/0/points", "segment 1 has zero length"},
    {"cut_self_intersecting", "/shells/0/cuts", R"([{"points": [[0.2, 0.2], [0.8, 0.8], [0.8, 0.2], [0.2, 0.8]]}])",
     "/shells/0/cuts/0/points", "segment 0 intersects segment 2 (self-intersecting polyline)"},
    {"cut_closed_two_points", "/shells/0/cuts", R"([{"points": [[0.2, 0.2], [0.8, 0.8]], "closed": true}])",
     "/shells/0/cuts/0/points", "expected at least 3 points [u, v], got 2"},
    {"cut_single_point", "/shells/1/cuts", R"([{"points": [[0.5, 0.5]]}])", "/shells/1/cuts/0/points",
     "expected at least 2 points [u, v], got 1"},
    // Crack machinery settings.
    {"cracks_unknown_key", "/cracks", R"({"extraction_every": 5})", "/cracks/extraction_every",
     "unknown key \"extraction_every\": allowed here are"},
    {"cracks_zero_extraction_interval", "/cracks", R"({"extraction_interval": 0})", "/cracks/extraction_interval",
     "value 0 is out of range: must be in [1, 1000000]"},
    {"cracks_shadow_offset_too_large", "/cracks", R"({"shadow_offset": 0.05})", "/cracks/shadow_offset",
     "value 0.05 is out of range: must be in (0, 0.01)"},
    {"cracks_zero_shadow_offset", "/cracks", R"({"shadow_offset": 0})", "/cracks/shadow_offset",
     "value 0 is out of range: must be in (0, 0.01)"},
    {"cracks_unknown_tip_weights", "/cracks", R"({"tip_weights": "transparency"})", "/cracks/tip_weights",
     "unknown value \"transparency\": allowed are \"visibility\", \"diffraction\""},
    {"cracks_tip_weights_not_a_string", "/cracks", R"({"tip_weights": 2})", "/cracks/tip_weights", "string"},
    {"cracks_unknown_support", "/cracks", R"({"support": "smooth"})", "/cracks/support",
     "unknown value \"smooth\": allowed are \"continuous\", \"stepped\""},
    {"cracks_support_margin_too_small", "/cracks", R"({"support_margin": 1.0})", "/cracks/support_margin",
     "value 1 is out of range: must be in [1.1, 3]"},
};

INSTANTIATE_TEST_SUITE_P(AllRules, SceneValidation, ::testing::ValuesIn(kBadCases),
                         [](const auto& info) { return std::string(info.param.label); });

TEST(SceneParse, TipWeightsDefaultToDiffractionAndAcceptVisibility) {
  EXPECT_TRUE(build_model(valid_scene().dump(), "ok.json").cracks.tip_diffraction);
  Json j = valid_scene();
  j["cracks"] = Json::parse(R"({"tip_weights": "visibility"})");
  EXPECT_FALSE(build_model(j.dump(), "ok.json").cracks.tip_diffraction);
  j["cracks"] = Json::parse(R"({"tip_weights": "diffraction"})");
  EXPECT_TRUE(build_model(j.dump(), "ok.json").cracks.tip_diffraction);
}

TEST(SceneParse, SupportRuleDefaultsToContinuousAndAcceptsStepped) {
  const Model plain = build_model(valid_scene().dump(), "ok.json");
  EXPECT_TRUE(plain.cracks.continuous_support);
  EXPECT_EQ(plain.cracks.support_margin, 1.5);
  Json j = valid_scene();
  j["cracks"] = Json::parse(R"({"support": "continuous", "support_margin": 1.25})");
  const Model continuous = build_model(j.dump(), "ok.json");
  EXPECT_TRUE(continuous.cracks.continuous_support);
  EXPECT_EQ(continuous.cracks.support_margin, 1.25);
  j["cracks"] = Json::parse(R"({"support": "stepped"})");
  EXPECT_FALSE(build_model(j.dump(), "ok.json").cracks.continuous_support);
}

TEST(SceneParse, ValidSceneBuildsTheExpectedPatches) {
  const Model s = build_model(valid_scene().dump(), "ok.json");
  ASSERT_EQ(s.shells.size(), 3u);
  EXPECT_EQ(s.name, "t");
  EXPECT_DOUBLE_EQ(s.time.end, 0.1);
  EXPECT_DOUBLE_EQ(s.time.frame_rate, 30);
  EXPECT_FALSE(s.time.dt.has_value());
  // Flat 4 x 8 cells: cells + 2 control points per direction (thesis sec. 4.3.1).
  EXPECT_EQ(s.shells[0].surface.num_u(), 6);
  EXPECT_EQ(s.shells[0].surface.num_v(), 10);
  EXPECT_DOUBLE_EQ(s.shells[0].thickness, 0.001);
  // Lamé parameters (thesis Eq. 2.4): E = 1e5, nu = 0.3.
  EXPECT_NEAR(s.shells[0].material.mu(), 1e5 / 2.6, 1e-9);
  EXPECT_NEAR(s.shells[0].material.lambda(), 1e5 * 0.3 / (1.3 * 0.4), 1e-9);
  EXPECT_TRUE(s.shells[1].surface.is_rational());
  EXPECT_EQ(s.shells[1].surface.num_u(), 3);
  EXPECT_EQ(s.shells[1].surface.num_v(), 2);
  // Unnamed keys default: first shell named "a" explicitly.
  EXPECT_EQ(s.shells[0].name, "a");
}

TEST(SceneParse, ControlNetRefineKeepsGeometry) {
  Json j = valid_scene();
  j["shells"][1]["patch"]["refine"] = {3, 2};
  const Model coarse = build_model(valid_scene().dump(), "a.json");
  const Model fine = build_model(j.dump(), "b.json");
  const auto& a = coarse.shells[1].surface;
  const auto& b = fine.shells[1].surface;
  EXPECT_EQ(b.knots_u().num_spans(), 3);
  EXPECT_EQ(b.knots_v().num_spans(), 2);
  double worst = 0;
  for (int i = 0; i <= 20; ++i)
    for (int k = 0; k <= 20; ++k)
      worst = std::max(worst, (a.point(i / 20.0, k / 20.0) - b.point(i / 20.0, k / 20.0)).norm());
  EXPECT_LE(worst, 1e-12);
}

TEST(SceneParse, ControlNetElevateKeepsGeometryAndRaisesTheDegree) {
  // elevate then refine (k-refinement): degrees (3, 3), the same rational surface to 1e-14.
  Json j = valid_scene();
  j["shells"][1]["patch"]["elevate"] = {1, 2};
  j["shells"][1]["patch"]["refine"] = {2, 2};
  const Model coarse = build_model(valid_scene().dump(), "a.json");
  const Model fine = build_model(j.dump(), "b.json");
  const auto& a = coarse.shells[1].surface;
  const auto& b = fine.shells[1].surface;
  EXPECT_EQ(b.knots_u().degree(), 3);
  EXPECT_EQ(b.knots_v().degree(), 3);
  EXPECT_EQ(b.knots_u().multiplicity(0.5), 1);
  double worst = 0;
  for (int i = 0; i <= 20; ++i)
    for (int k = 0; k <= 20; ++k)
      worst = std::max(worst, (a.point(i / 20.0, k / 20.0) - b.point(i / 20.0, k / 20.0)).norm());
  EXPECT_LE(worst, 1e-14);
  // The built-in shapes take "degree".
  j = valid_scene();
  j["shells"][0]["patch"]["degree"] = {3, 4};
  const Model raised = build_model(j.dump(), "c.json");
  EXPECT_EQ(raised.shells[0].surface.num_u(), 4 + 3);
  EXPECT_EQ(raised.shells[0].surface.num_v(), 8 + 4);
}

TEST(SceneParse, InvalidJsonReportsLineAndColumn) {
  try {
    build_model("{\n  \"shells\": [\n    1,\n  ]\n}", "broken.json");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("broken.json"));
    EXPECT_THAT(e.message(), HasSubstr("line 4, column 3"));
  }
}

TEST(SceneParse, DegenerateControlNetIsBadInputWhenSimulated) {
  // Valid NURBS, but every control point on one line: the shell has no tangent plane.
  Json j = valid_scene();
  j["shells"][1]["patch"]["control_points"] = Json::parse("[[0,0,0],[1,0,0],[2,0,0],[3,0,0],[4,0,0],[5,0,0]]");
  const Model s = build_model(j.dump(), "line.json");
  try {
    Simulation sim(s);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/shells/1/patch");
    EXPECT_THAT(e.message(), HasSubstr("degenerate"));
  }
}

// The damage law needs G_f > sigma_f^2 l_ch / (2 E) with l_ch = sqrt(3) dx (thesis Eq. 2.28); the grid
// spacing is only known to the Simulation, so the check runs when it is constructed (sim/cracks.cpp).
TEST(SceneParse, FractureEnergyTooSmallForTheGridIsBadInputWhenSimulated) {
  auto scene_with = [](double fracture_energy) {
    Json j = valid_scene();
    j["grid"] = {{"dx", 0.1}};
    j["shells"][0]["material"]["fracture"] = {{"failure_stress", 1e4}, {"fracture_energy", fracture_energy}};
    return build_model(j.dump(), "frac.json");
  };
  // E = 1e5 Pa, sigma_f = 1e4 Pa, l_ch = sqrt(3) 0.1 m: the minimum is 1e8 sqrt(3) 0.1 / 2e5 = 86.6025 J/m^2.
  const double minimum = 1e4 * 1e4 * std::sqrt(3.0) * 0.1 / (2.0 * 1e5);
  EXPECT_NEAR(minimum, 86.6025, 1e-4);
  try {
    Simulation sim(scene_with(80.0));
    FAIL() << "fracture energy below the minimum was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "frac.json");
    EXPECT_EQ(e.json_path(), "/shells/0/material/fracture/fracture_energy") << e.what();
    EXPECT_THAT(e.message(), HasSubstr("fracture energy 80 J/m^2 is too small")) << e.what();
    EXPECT_THAT(e.message(), HasSubstr("G_f > sigma_f^2 l_ch / (2 E) = 86.6025 J/m^2")) << e.what();
    EXPECT_THAT(e.message(), HasSubstr("l_ch = sqrt(3) dx = 0.173205 m")) << e.what();
    EXPECT_THAT(std::string(e.what()), HasSubstr("frac.json: /shells/0/material/fracture/fracture_energy"));
  }
  // Just above the minimum the same scene is accepted.
  EXPECT_NO_THROW({ Simulation sim(scene_with(90.0)); });
}

TEST(SceneParse, MissingFileIsASceneError) {
  EXPECT_THROW(load_model("/nonexistent/scene.json"), SceneError);
}

}  // namespace
}  // namespace shellfrac::scene
