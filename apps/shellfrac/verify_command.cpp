// `shellfrac verify coupling`: runs a coupled scene and checks its seams against the scene's limits.
#include "apps/shellfrac/verify_command.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "sim/progress.hpp"
#include "sim/run.hpp"
#include "sim/scene.hpp"
#include "sim/scene_error.hpp"
#include "sim/seam_metrics.hpp"

namespace shellfrac::app {

namespace {

struct VerifyOptions {
  std::string scene_path;
  std::string out_dir = "out";
  int threads = 0;
};

std::string number(const nlohmann::json& v) {
  if (v.is_null()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v.get<double>());
  return buf;
}

// One line per metric of every interface; returns the number of failed checks.
int print_table(const nlohmann::json& interfaces, std::ostream& out) {
  char line[256];
  std::snprintf(line, sizeof line, "%-15s %-28s %-5s %-19s %-11s %-11s %-6s %s\n", "interface", "leader -> follower",
                "cont.", "metric", "max", "limit", "frame", "result");
  out << line;
  int failed = 0, checked = 0;
  for (const auto& seam : interfaces) {
    const std::string edges = seam["leader"].get<std::string>() + " -> " + seam["follower"].get<std::string>();
    bool first = true;
    for (const auto& [key, label] : {std::pair{"gap", "gap [m]"}, std::pair{"angle_degrees", "normal angle [deg]"},
                                     std::pair{"stress_ratio", "stress ratio"}}) {
      const auto& c = seam["checks"][key];
      const std::string result = c["result"];
      failed += result == "fail";
      checked += result == "pass" || result == "fail";
      std::snprintf(line, sizeof line, "%-15s %-28s %-5s %-19s %-11s %-11s %-6s %s\n",
                    first ? seam["interface"].get<std::string>().c_str() : "", first ? edges.c_str() : "",
                    first ? seam["continuity"].get<std::string>().c_str() : "", label, number(c["max"]).c_str(),
                    number(c["limit"]).c_str(), c["frame"].is_null() ? "-" : std::to_string(c["frame"].get<int>()).c_str(),
                    result.c_str());
      out << line;
      first = false;
    }
  }
  out << (failed ? "FAIL: " + std::to_string(failed) + " of " + std::to_string(checked) + " checks failed\n"
                 : "PASS: all " + std::to_string(checked) + " checks passed\n");
  return failed;
}

int run_verify(const VerifyOptions& o) {
  try {
    const sim::Scene scene = sim::load_scene_file(o.scene_path);
    if (sim::scene_seams(scene).empty())
      throw sim::SceneError(scene.source, "/interfaces",
                            "the scene declares no interfaces: nothing to verify (add \"interfaces\", see "
                            "docs/scene-format.md)");
    sim::RunOptions run;
    run.out_dir = o.out_dir;
    run.threads = o.threads;
    run.interactive = sim::Progress::stderr_is_terminal();
    std::cerr << "verify coupling: running " << sim::describe_scene(scene);
    const nlohmann::json summary = sim::run_scene(scene, run, std::cerr);
    std::cout << "seam checks of scene \"" << scene.name << "\" over " << summary["frames"].size()
              << " frames (model size " << sim::model_size(scene) << " m; series in " << o.out_dir
              << "/summary.json, metrics.interfaces)\n";
    return print_table(summary["metrics"]["interfaces"], std::cout) ? kExitCheckFailed : 0;
  } catch (const sim::SceneError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const sim::NumericalError& e) {
    std::cerr << "numerical failure: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

std::function<std::optional<int>()> add_verify_command(CLI::App& app) {
  auto options = std::make_shared<VerifyOptions>();
  auto* verify = app.add_subcommand("verify", "Run a scene and check it against its verification limits.");
  verify->require_subcommand(1);
  auto* coupling = verify->add_subcommand(
      "coupling", "Run a scene with patch interfaces like `run`, then print a pass/fail table of every "
                  "interface's seam gap, normal angle and seam stress ratio against the limits in the scene "
                  "(exit 0 all pass, 4 a check failed).");
  coupling->add_option("scene", options->scene_path, "Scene file (JSON) with \"interfaces\"")->required();
  coupling->add_option("--out,-o", options->out_dir, "Output directory")->capture_default_str();
  coupling->add_option("--threads,-j", options->threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  return [options, coupling]() -> std::optional<int> {
    if (!coupling->parsed()) return std::nullopt;
    return run_verify(*options);
  };
}

}  // namespace shellfrac::app
