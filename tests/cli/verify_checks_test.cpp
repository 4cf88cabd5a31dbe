// `verify coupling` checks by default: the seam stress ratio and, for the whole scene, the
// render mesh's peak edge stretch (top-level "verify": {"max_edge_stretch"}); a spike fails with exit 4.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::ContainsRegex;
using ::testing::HasSubstr;

using shellfrac::test::Result;

Result verify(const fs::path& scene, const fs::path& out) {
  return shellfrac::test::run_shellfrac("verify coupling " + scene.string() + " --out " + out.string() + " --threads 2");
}

fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("verify", name); }

// Two tiny nested patches (4 and 8 cells along the seam) falling for 0.1 s, with `extra` top-level keys.
std::string tiny(const std::string& extra) {
  return R"({"name": "tiny-seam", "time": {"end": 0.1, "frame_rate": 20}, "output": {"resolution": [2, 2]},
    "shells": [
      {"name": "left", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [2, 4], "origin": [-0.5, 0, 0]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}},
      {"name": "right", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [2, 8], "origin": [0, 0, 0]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}],
    "interfaces": [{"a": {"shell": "left", "side": "u1"}, "b": {"shell": "right", "side": "u0"}}])" +
         extra + "}";
}

TEST(VerifyChecks, EdgeStretchRowHasADefaultAndASceneKey) {
  const fs::path d = scratch("rows");
  // Default: a sheet in free fall keeps its edges (stretch 1 to round-off) below the limit 3.
  std::ofstream(d / "default.json") << tiny("");
  const Result ok = verify(d / "default.json", d / "ok");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_THAT(ok.output, ContainsRegex("peak edge stretch +1(\\.0+)? +3 +[0-9]+ +pass"));
  EXPECT_THAT(ok.output, ContainsRegex("stress ratio +[-0-9.e]+ +1e\\+04 "));  // the default seam limit
  std::ifstream in(d / "ok" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_NEAR(s["metrics"]["peak_edge_stretch"]["value"].get<double>(), 1.0, 1e-6);
  // A limit below any mesh's stretch (synthetic: every edge keeps at least its rest length here) fails.
  std::ofstream(d / "strict.json") << tiny(R"(, "verify": {"max_edge_stretch": 0.5})");
  const Result strict = verify(d / "strict.json", d / "strict");
  EXPECT_EQ(strict.exit_code, 4) << strict.output;
  EXPECT_THAT(strict.output, ContainsRegex("peak edge stretch +[0-9.]+ +0.5 +[0-9]+ +fail"));
  EXPECT_THAT(strict.output, HasSubstr("FAIL: 1 of"));
  // null switches the row off.
  std::ofstream(d / "off.json") << tiny(R"(, "verify": {"max_edge_stretch": null})");
  const Result off = verify(d / "off.json", d / "off");
  EXPECT_EQ(off.exit_code, 0) << off.output;
  EXPECT_THAT(off.output, ContainsRegex("peak edge stretch +[0-9.]+ +- +[0-9]+ +unchecked"));
  // Bad values name their key.
  std::ofstream(d / "bad.json") << tiny(R"(, "verify": {"max_edge_stretch": -1})");
  const Result bad = verify(d / "bad.json", d / "bad");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("/verify/max_edge_stretch"));
  fs::remove_all(d);
}

TEST(VerifyChecks, TheLSheetWithLeastSquaresSeamsFails) {
  // scenes/l-sheet-three-patch.json with the thesis's least-squares seams (the former default):
  // once the crack crosses them the seams open (6.6e-5 m and 3.7e-5 m against a limit of 1e-9 x the
  // model size), and verify fails with exit 4 on both gap rows. (Before the crack-closure merge the torn
  // corner's edge was also dragged into a spike of peak edge stretch 3.2e4; with the closed crack graph it
  // measures 4.6, so the spike is no longer what fails.) The shipped scene, with exact closure, passes
  // (ctest verify_coupling.l-sheet-three-patch).
  const fs::path d = scratch("lsheet");
  std::ifstream in(std::string(SHELLFRAC_SOURCE_DIR) + "/scenes/l-sheet-three-patch.json");
  nlohmann::json j = nlohmann::json::parse(in);
  for (auto& i : j["interfaces"]) i["closure"] = "least_squares";
  std::ofstream(d / "lsq.json") << j.dump();
  const Result r = verify(d / "lsq.json", d / "out");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_THAT(r.output, ContainsRegex("/interfaces/0 .* gap \\[m\\] +[0-9.e+-]+ +1.414e-09 +[0-9]+ +fail"));
  EXPECT_THAT(r.output, ContainsRegex("/interfaces/1 .* gap \\[m\\] +[0-9.e+-]+ +1.414e-09 +[0-9]+ +fail"));
  fs::remove_all(d);
}

}  // namespace
