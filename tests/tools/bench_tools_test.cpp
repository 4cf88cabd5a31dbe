// The benchmark tooling: convergence fits and Pareto fronts on synthetic data, the quality presets, and
// the tiny speed-accuracy sweep and stability map (files written, numbers in them, an unstable step
// classified as a failure). No test here depends on wall-clock time.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/quality.hpp"
#include "scene/scene_error.hpp"
#include "sim/simulation.hpp"
#include "tools/bench_sweep.hpp"
#include "tools/charts.hpp"
#include "tools/stability_map.hpp"

namespace shellfrac::tools {

namespace {

namespace fs = std::filesystem;

// CSV rows as maps from header name to cell (the tool's CSV has no quoted commas in these columns).
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : s) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
      else cell += c;
    }
    cells.push_back(cell);
    return cells;
  };
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

bool is_png(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in && std::string(sig + 1, 3) == "PNG" && fs::file_size(path) > 1000;
}

fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("shellfrac-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

TEST(BenchTools, ConvergenceFitRecoversTheOrderOfSyntheticData) {
  std::vector<double> h, e2, e3;
  for (double x : {0.2, 0.1, 0.05, 0.025, 0.0125}) {
    h.push_back(x);
    e2.push_back(3.0 * x * x);        // error = C h^2
    e3.push_back(0.5 * x * x * x);    // error = C h^3
  }
  const auto fit2 = charts::fit_convergence_order(h, e2);
  EXPECT_NEAR(fit2.order, 2.0, 1e-9);
  EXPECT_NEAR(fit2.log_constant, std::log(3.0), 1e-9);
  EXPECT_EQ(fit2.points, 5);
  EXPECT_NEAR(charts::fit_convergence_order(h, e3).order, 3.0, 1e-9);
  // Non-positive errors are left out; one usable point gives no order.
  EXPECT_TRUE(std::isnan(charts::fit_convergence_order({0.1, 0.05}, {0.0, 1e-3}).order));
}

TEST(BenchTools, ParetoFrontIsTheNonDominatedSubset) {
  //                        cost:  1    2    3    4     0.5  2    5
  const std::vector<double> cost{1.0, 2.0, 3.0, 4.0, 0.5, 2.0, 5.0};
  const std::vector<double> err{0.5, 0.2, 0.3, 0.05, 1.0, 0.25, 0.05};
  // (3, 0.3) is beaten by (2, 0.2); (2, 0.25) by (2, 0.2); (5, 0.05) by (4, 0.05).
  const std::vector<bool> expected{true, true, false, true, true, false, false};
  EXPECT_EQ(charts::pareto_front(cost, err), expected);
}

TEST(BenchTools, HangingStripElongationHasTheLinearLimit) {
  // Small strain: rho g L^2 / (2 E). With mu = E / 2 the stretch is s = q/2 + sqrt(1 + q^2/4) with
  // q = 2 rho g (L - S) / E, so s - 1 = q/2 + q^2/8 + O(q^4): the next term of the elongation is
  // (rho g / E)^2 L^3 / 6, and what is left is below 1e-6 of the whole at 2% strain.
  const double linear = 200 * 9.81 * 0.25 / (2 * 1e9);
  EXPECT_NEAR(hanging_strip_elongation(1e9, 200, 9.81, 0.5), linear, 1e-6 * linear);
  const double a = 200 * 9.81 / 1e5;
  const double second_order = 0.5 * a * 0.25 + a * a * 0.125 / 6;
  EXPECT_NEAR(hanging_strip_elongation(1e5, 200, 9.81, 0.5), second_order, 1e-6 * second_order);
}

TEST(BenchTools, QualityDefaultLeavesEverySceneUnchanged) {
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    scene::Scene s = scene::load_scene(entry.path().string());
    const nlohmann::json original = scene::to_json(s);
    s.quality = "default";
    scene::apply_quality(s);
    EXPECT_EQ(scene::to_json(s), original) << entry.path();
    ++scenes;
  }
  EXPECT_GE(scenes, 10);
}

TEST(BenchTools, QualityPresetsRewriteTheDiscretisation) {
  const std::string base = R"({"shells": [{"patch": {"type": "flat", "size": [1, 1], "cells": [10, 6]},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}},
     {"patch": {"type": "flat", "size": [1, 1], "cells": [4, 4]}, "quadrature": {"points": 3},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}}])";
  const scene::Model draft = scene::build_model(base + R"(, "quality": "draft"})", "q.json");
  const scene::Model high = scene::build_model(base + R"(, "quality": "high"})", "q.json");
  const scene::Model plain = scene::build_model(base + "}", "q.json");
  EXPECT_EQ(draft.shells[0].quadrature.points_per_direction, 2);
  EXPECT_EQ(draft.shells[1].quadrature.points_per_direction, 3);  // explicit settings win
  EXPECT_DOUBLE_EQ(draft.time.cfl, plain.time.cfl);
  EXPECT_EQ(draft.shells[0].surface.knots_u().num_spans(), 10);
  EXPECT_EQ(high.shells[0].surface.knots_u().num_spans(), 20);
  EXPECT_EQ(high.shells[0].surface.knots_v().num_spans(), 12);
  EXPECT_EQ(high.shells[0].quadrature.points_per_direction, 4);
  EXPECT_DOUBLE_EQ(high.time.cfl, plain.time.cfl);
  try {
    scene::build_model(base + R"(, "quality": "ultra"})", "q.json");
    FAIL() << "accepted an unknown quality";
  } catch (const scene::SceneError& e) {
    EXPECT_EQ(e.json_path(), "/quality");
    EXPECT_EQ(e.message(), "expected draft, default or high, got \"ultra\"");
  }
}

TEST(BenchTools, TinySweepWritesItsFilesAndNumbers) {
  SweepConfig config;
  config.out_dir = scratch_dir("sweep");
  config.charts = charts::gnuplot_available();
  std::ostringstream log;
  const auto rows = run_sweep(config, log);
  size_t planned = 0;
  for (const auto& b : accuracy_benchmarks(false)) planned += sweep_plan(b).size();
  ASSERT_EQ(rows.size(), planned);

  const auto csv = read_csv(config.out_dir / "sweep.csv");
  ASSERT_EQ(csv.size(), planned);
  std::map<std::string, std::vector<double>> mls_error;
  for (size_t i = 0; i < csv.size(); ++i) {
    const double error = std::stod(csv[i].at("error"));
    EXPECT_TRUE(std::isfinite(error) && error >= 0) << csv[i].at("benchmark");
    EXPECT_NEAR(error, rows[i].m.error, 1e-8 * std::max(1e-300, std::abs(rows[i].m.error)));  // 9 digits
    if (csv[i].at("benchmark") == "mls") mls_error[csv[i].at("cells")].push_back(error);
  }
  // The hanging strip's reference is the exact elongation.
  EXPECT_NEAR(std::stod(csv[0].at("reference")), hanging_strip_elongation(1e5, 200, 9.81, 0.5), 1e-12);
  // MLS quasi-interpolation of a smooth field: refining 4 -> 8 cells cuts the error by more than 4
  // (third order would be 8).
  ASSERT_EQ(mls_error["4"].size(), 1u);
  EXPECT_GT(mls_error["4"][0] / mls_error["8"][0], 4.0);
  const auto convergence = read_csv(config.out_dir / "convergence.csv");
  bool found = false;
  for (const auto& r : convergence)
    if (r.at("benchmark") == "mls") {
      found = true;
      EXPECT_GT(std::stod(r.at("order")), 2.0);
      EXPECT_LT(std::stod(r.at("order")), 5.0);
    }
  EXPECT_TRUE(found);
  // Stage seconds of the tearing run: the step stages are all there and add up to a positive time.
  const auto stages = read_csv(config.out_dir / "stages.csv");
  std::map<std::string, double> share;
  for (const auto& s : stages) share[s.at("stage")] = std::stod(s.at("share"));
  for (const char* stage : {"p2g", "forces", "grid_update", "g2p"}) EXPECT_TRUE(share.count(stage)) << stage;
  double total = 0;
  for (const auto& [name, s] : share) total += s;
  EXPECT_NEAR(total, 1.0, 1e-6);
  // The crack-speed study: the coarse bar under both models. Regression check: Rankine's crack starts at the
  // notch before the tiny run's 4 ms end (measured 2.79 ms), the phase field's not yet (4.26 ms).
  const auto speed = read_csv(config.out_dir / "crack_speed_summary.csv");
  ASSERT_EQ(speed.size(), 2u);
  std::map<std::string, double> start;
  for (const auto& r : speed) start[r.at("model")] = std::stod(r.at("start_time"));
  EXPECT_GT(start.at("rankine"), 0.0);
  EXPECT_LT(start.at("rankine"), 0.004);
  EXPECT_LT(start.at("phase_field"), 0.0);  // -1: never in the run
  EXPECT_FALSE(read_csv(config.out_dir / "crack_speed.csv").empty());
  if (config.charts) {
    for (const char* png : {"membrane-error-vs-time.png", "membrane-error-vs-resolution.png",
                            "mls-error-vs-resolution.png", "tear-stage-breakdown.png", "crack-tip-bar.png"})
      EXPECT_TRUE(is_png(config.out_dir / png)) << png;
  }
  fs::remove_all(config.out_dir);
}

TEST(BenchTools, TinyStabilityMapClassifiesAnUnstableStepAsAFailure) {
  StabilityConfig config;
  config.out_dir = scratch_dir("stability");
  config.charts = charts::gnuplot_available();
  std::ostringstream table, log;
  const auto results = run_stability_map(config, table, log);
  ASSERT_EQ(results.size(), stability_cases(false).size());
  const auto csv = read_csv(config.out_dir / "stability.csv");
  ASSERT_EQ(csv.size(), results.size());
  std::map<std::string, std::map<std::string, std::string>> outcome;  // scene -> variant -> outcome
  for (const auto& r : csv) outcome[r.at("scene")][r.at("variant")] = r.at("outcome");
  // The tiny tear stops long before it tears: nothing can fail. (The tiny drape's render mesh comes
  // within half a cell of the ball, so its default outcome is not asserted here.)
  EXPECT_EQ(outcome["tear"]["default"], "completed");
  EXPECT_EQ(outcome["tear"]["dt 0.5x bound"], "completed");
  EXPECT_EQ(outcome["tear"]["mass scaling 1%"], "completed");
  {
    // The tiny tear's notch gives MLS bases from the first step; 1 % added mass beside it widens the step.
    std::map<std::string, double> dt_ratio;
    for (const auto& r : csv)
      if (r.at("scene") == "tear") dt_ratio[r.at("variant")] = std::stod(r.at("dt_over_bound"));
    EXPECT_GT(dt_ratio.at("mass scaling 1%"), dt_ratio.at("default"));
  }
  for (const char* scene : {"tear", "drape"}) {
    EXPECT_NE(outcome[scene]["dt 0.5x bound"], "NaN") << scene;
    EXPECT_NE(outcome[scene]["dt 0.5x bound"], "energy blow-up") << scene;
    EXPECT_EQ(outcome[scene]["dt 2x bound (check on)"], "refused") << scene;
    // Four times the bound, run anyway: not a completed run.
    EXPECT_NE(outcome[scene]["dt 4x bound"], "completed") << scene;
    EXPECT_NE(outcome[scene]["dt 4x bound"], "refused") << scene;
  }
  // At or below the bound the check stays on, so the step is the factor or the basis-aware bound of the
  // cut sheet (docs/fracture.md sec. 3), whichever is smaller: the tiny tear's notch gives MLS bases from
  // the first step and its crack does not grow, so that bound is the one of the built simulation.
  for (const StabilityCase& c : stability_cases(false)) {
    if (c.variant != "dt 0.5x bound" && c.variant != "dt 1x bound") continue;
    const sim::Simulation built(c.definition);
    const double basis_ratio = built.current_elastic_wave_bound() / built.elastic_wave_bound();
    for (const auto& r : csv) {
      if (r.at("scene") != c.scene || r.at("variant") != c.variant) continue;
      EXPECT_NEAR(std::stod(r.at("dt_over_bound")), std::min(c.dt_factor, basis_ratio), 1e-9) << c.scene << " " << c.variant;
    }
  }
  // The pulled notched bar under Rankine damage breaks into its two halves; cfl 2 is refused.
  EXPECT_EQ(outcome["bar"]["default"], "completed");
  EXPECT_EQ(outcome["bar"]["dt 2x bound (check on)"], "refused");
  EXPECT_NE(table.str().find("refused"), std::string::npos);
  if (config.charts) {
    EXPECT_TRUE(is_png(config.out_dir / "stability-map.png"));
  }
  fs::remove_all(config.out_dir);
}

// The full map's solid rows: each method completes on the bar at its defaults and fails where it is taken
// out of its range. The counts are those of the fracture events (slivers apart), the same as summary.json.
TEST(BenchTools, SolidRowsShowEachDamageModelFailing) {
  std::map<std::string, StabilityCase> cases;
  for (const StabilityCase& c : stability_cases(true))
    if (c.scene == "bar" || c.scene == "beam") cases[c.scene + " / " + c.variant] = c;
  auto run = [&](const std::string& name) {
    EXPECT_TRUE(cases.count(name)) << name;
    return run_stability_case(cases.at(name), 0);
  };
  for (const char* name : {"bar / default", "bar / phase field", "bar / NACC", "beam / default"}) {
    const StabilityResult r = run(name);
    EXPECT_EQ(r.outcome, Outcome::completed) << name << ": " << r.tripped_by << " " << r.detail;
    EXPECT_EQ(r.fragments, 2) << name;
  }
  // NACC without cohesion (beta 0) yields in tension at the grips' edges first: the two ends come off
  // besides the crack, three pieces.
  const StabilityResult loose = run("bar / NACC beta 0");
  EXPECT_EQ(loose.outcome, Outcome::shattered);
  EXPECT_EQ(loose.fragments, 3);
  // The phase field's strength grows as l0 shrinks (sigma_c ~ sqrt(G E / l0)); at l0 = 0.02 dx the bar
  // does not break in the 10 ms of pulling.
  const StabilityResult thin = run("bar / phase field l0 0.02 dx");
  EXPECT_EQ(thin.outcome, Outcome::glued);
  EXPECT_EQ(thin.fragments, 1);
  // In three-point bending the phase field's split degrades shear under the load: no crack at the notch.
  EXPECT_EQ(run("beam / phase field").outcome, Outcome::glued);
}

// Runs the shellfrac binary; returns the exit code and the combined output.
std::pair<int, std::string> run_cli(const std::string& args) {
  const std::string cmd = std::string(SHELLFRAC_BIN) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(BenchTools, CliBenchWritesCsvAndRejectsBadInput) {
  const fs::path out = scratch_dir("cli");
  const auto [code, text] = run_cli("bench sweep --config tiny --no-charts --out " + out.string());
  EXPECT_EQ(code, 0) << text;
  EXPECT_TRUE(fs::exists(out / "sweep.csv"));
  EXPECT_FALSE(fs::exists(out / "membrane-error-vs-time.png"));  // --no-charts
  const auto [bad_code, bad_text] = run_cli("bench stability --config huge");
  EXPECT_EQ(bad_code, 2) << bad_text;
  // A scene with an unknown quality is bad input naming /quality.
  fs::create_directories(out);
  std::ofstream(out / "q.json") << R"({"quality": "ultra", "shells": []})";
  const auto [q_code, q_text] = run_cli("validate " + (out / "q.json").string());
  EXPECT_EQ(q_code, 2);
  EXPECT_NE(q_text.find("/quality: expected draft, default or high, got \"ultra\""), std::string::npos) << q_text;
  fs::remove_all(out);
}

}  // namespace
}  // namespace shellfrac::tools
