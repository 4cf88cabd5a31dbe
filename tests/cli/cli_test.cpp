#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using shellfrac::test::Result;

Result shellfrac(const std::string& args) { return shellfrac::test::run_shellfrac(args); }

fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("cli", name); }

TEST(Cli, VersionAndHelpExitZero) {
  const Result v = shellfrac("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_THAT(v.output, HasSubstr("shellfrac 0."));
  for (const char* cmd : {"--help", "run --help", "validate --help"}) {
    const Result h = shellfrac(cmd);
    EXPECT_EQ(h.exit_code, 0) << cmd;
    EXPECT_THAT(h.output, HasSubstr("Usage")) << cmd;
  }
}

TEST(Cli, UsageErrorsAreBadInput) {
  EXPECT_EQ(shellfrac("").exit_code, 2);
  EXPECT_EQ(shellfrac("frobnicate").exit_code, 2);
  EXPECT_EQ(shellfrac("validate").exit_code, 2);
  EXPECT_EQ(shellfrac("run --threads -3").exit_code, 2);
}

TEST(Cli, ValidateAcceptsEveryShippedScene) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes")) {
    if (e.path().extension() != ".json") continue;
    ++count;
    const Result r = shellfrac("validate " + e.path().string());
    EXPECT_EQ(r.exit_code, 0) << e.path() << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(": OK"));
  }
  EXPECT_GE(count, 4);
}

TEST(Cli, ValidateRejectsBrokenSceneWithPath) {
  const fs::path d = scratch("broken");
  std::ofstream(d / "bad.json") << R"({"shells": [{"patch": {"type": "flat", "size": [1, 1],
    "cells": [4, 4]}, "thickness": 0.001, "material": {"E": 1e5, "nu": 0.7, "density": 100}}]})";
  const Result r = shellfrac("validate " + (d / "bad.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("bad.json: /shells/0/material/nu"));
  EXPECT_THAT(r.output, HasSubstr("in (-1, 0.5)"));
  const Result missing = shellfrac("validate " + (d / "nope.json").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.output, HasSubstr("nope.json"));
  // run refuses the same scene before writing anything.
  const Result run = shellfrac("run " + (d / "bad.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
  fs::remove_all(d);
}

TEST(Cli, MeshThatFailsToImportIsBadInput) {
  const fs::path d = scratch("badmesh");
  std::ofstream(d / "broken.obj") << "this is not a mesh\n";
  std::ofstream(d / "scene.json") << R"({"solids": [{"shape": "mesh", "file": "broken.obj", "spacing": 0.05,
    "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})";
  const Result r = shellfrac("validate " + (d / "scene.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/solids/0/file"));
  EXPECT_THAT(r.output, HasSubstr("broken.obj"));
  fs::remove_all(d);
}

TEST(Cli, RunDefaultWritesSummaryAndMesh) {
  const fs::path d = scratch("run");
  const Result r = shellfrac("run --out " + d.string() + " --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(d / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "completed");
  EXPECT_EQ(s["threads"], 1);
  EXPECT_TRUE(s["metrics"].is_object());
  EXPECT_TRUE(s["stage_seconds"].contains("output"));
  EXPECT_GE(s["wall_seconds"].get<double>(), 0.0);
  // Default scene: a 16 x 16-cell cloth, (cells + 2)^2 control points, 16 x 16 x 4 x 4 x 3 quadrature points.
  EXPECT_EQ(s["particle_counts"]["control_points"], 18 * 18);
  EXPECT_EQ(s["particle_counts"]["quadrature_points"], 16 * 16 * 48);
  // 0.5 s at 24 frames/s: frames 0..12, and steps no larger than the stability bound.
  EXPECT_EQ(s["frames"].size(), 13u);
  EXPECT_GT(s["steps"].get<long>(), 0);
  EXPECT_LE(s["dt"].get<double>(), s["stable_dt_bound"].get<double>() * (1 + 1e-12));
  EXPECT_NEAR(s["simulated_seconds"].get<double>(), 0.5, 1e-12);
  // The cloth falls onto the ball and stays outside it (within half a grid cell).
  EXPECT_LE(s["metrics"]["max_collider_penetration_cells"].get<double>(), 0.5);
  ASSERT_GE(s["frames"].size(), 1u);
  const fs::path mesh = d / s["frames"][0].get<std::string>();
  ASSERT_TRUE(fs::exists(mesh)) << mesh;
  // One patch at the 48 x 48 render resolution.
  std::ifstream obj(mesh);
  std::string line;
  int vertices = 0, faces = 0;
  while (std::getline(obj, line)) {
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) == 0) ++faces;
  }
  EXPECT_EQ(vertices, 49 * 49);
  EXPECT_EQ(faces, 48 * 48);
  fs::remove_all(d);
}

TEST(Cli, NumericalFailureExitsThreeAndKeepsFrames) {
  // A step 26x above the stability bound (allowed only for stability studies) blows up.
  const fs::path d = scratch("blowup");
  std::ofstream(d / "unstable.json") << R"({"time": {"end": 1.0, "frame_rate": 24, "dt": 0.05,
    "enforce_stability_bound": false}, "output": {"resolution": [8, 8]},
    "shells": [{"name": "cloth", "patch": {"type": "flat", "size": [1, 1], "cells": [16, 16]},
                "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}],
    "pins": [{"shell": "cloth", "region": {"u": [0, 0.05], "v": [0, 0.05]}}]})";
  const Result r = shellfrac("run " + (d / "unstable.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr("shell \"cloth\""));
  EXPECT_THAT(r.output, HasSubstr("at step"));
  std::ifstream in(d / "out" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "failed");
  EXPECT_THAT(s["error"].get<std::string>(), HasSubstr("cloth"));
  ASSERT_GE(s["frames"].size(), 1u);
  // Every frame listed is complete: 9 x 9 vertices, 64 faces, and no temporary files remain.
  for (const auto& f : s["frames"]) {
    std::ifstream obj(d / "out" / f.get<std::string>());
    std::string line;
    int vertices = 0, faces = 0;
    while (std::getline(obj, line)) {
      vertices += line.rfind("v ", 0) == 0;
      faces += line.rfind("f ", 0) == 0;
    }
    EXPECT_EQ(vertices, 81);
    EXPECT_EQ(faces, 64);
  }
  for (const auto& e : fs::directory_iterator(d / "out" / "frames"))
    EXPECT_EQ(e.path().filename().string().rfind(".", 0), std::string::npos) << e.path();
  fs::remove_all(d);
}

// `verify coupling` on two tiny patches (4 and 8 cells along the seam, nested) in free fall for 0.1 s.
std::string seam_scene(const std::string& interface_fields, const std::string& extra = "") {
  return R"({"name": "tiny-seam", "time": {"end": 0.1, "frame_rate": 20}, "output": {"resolution": [2, 2]},
    "shells": [
      {"name": "left", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [2, 4], "origin": [-0.5, 0, 0]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}},
      {"name": "right", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [2, 8], "origin": [0, 0, 0]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}],
    "interfaces": [{"a": {"shell": "left", "side": "u1"}, "b": {"shell": "right", "side": "u0"}, )" +
         interface_fields + "}]" + extra + "}";
}

TEST(Cli, VerifyCouplingPassesAndFails) {
  const fs::path d = scratch("verify");
  EXPECT_EQ(shellfrac("verify coupling --help").exit_code, 0);
  EXPECT_EQ(shellfrac("verify").exit_code, 2);
  // C1 with the default limits: the nested seam stays closed and flat (the stress is not measured in
  // free fall, which does not fail a check).
  std::ofstream(d / "pass.json") << seam_scene(R"("continuity": "C1", "verify": {"max_gap": 1e-9})");
  const Result pass = shellfrac("verify coupling " + (d / "pass.json").string() + " --out " + (d / "pass").string() +
                                " --threads 1");
  EXPECT_EQ(pass.exit_code, 0) << pass.output;
  EXPECT_THAT(pass.output, HasSubstr("PASS"));
  EXPECT_THAT(pass.output, HasSubstr("left.u1 -> right.u0"));
  std::ifstream in(d / "pass" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto& seam = s["metrics"]["interfaces"].at(0);
  EXPECT_EQ(seam["interface"], "/interfaces/0");
  EXPECT_EQ(seam["continuity"], "C1");
  EXPECT_EQ(seam["frames"].size(), 3u);
  EXPECT_LE(seam["checks"]["gap"]["max"].get<double>(), 1e-9);
  EXPECT_EQ(seam["checks"]["angle_degrees"]["limit"].get<double>(), 0.5);
  EXPECT_TRUE(seam["pass"].get<bool>());
  // Uncoupled, with the left half held at its far edge: only the shared grid nodes hold the free right
  // half, and the seam opens (measured 0.35 mm in 0.1 s) beyond a strict 1 micrometre limit: exit 4.
  std::ofstream(d / "fail.json") << seam_scene(R"("continuity": "none", "verify": {"max_gap": 1e-6})",
                                               R"(, "pins": [{"shell": "left", "region": {"u": [0, 0.1]}}])");
  const Result fail = shellfrac("verify coupling " + (d / "fail.json").string() + " --out " + (d / "fail").string() +
                                " --threads 1");
  EXPECT_EQ(fail.exit_code, 4) << fail.output;
  EXPECT_THAT(fail.output, HasSubstr("FAIL"));
  // Bad input stays exit 2: a scene without interfaces, a bad limit (with its JSON path).
  std::ofstream(d / "none.json") << R"({"shells": [{"patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]},
    "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})";
  const Result none = shellfrac("verify coupling " + (d / "none.json").string() + " --out " + (d / "x").string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_THAT(none.output, HasSubstr("no interfaces"));
  std::ofstream(d / "bad.json") << seam_scene(R"("verify": {"max_gap": -1})");
  const Result bad = shellfrac("verify coupling " + (d / "bad.json").string() + " --out " + (d / "x").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("/interfaces/0/verify/max_gap"));
  fs::remove_all(d);
}

}  // namespace
