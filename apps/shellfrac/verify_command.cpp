// `shellfrac verify coupling`: runs a coupled scene and checks its seams against the scene's limits.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "apps/shellfrac/command.hpp"
#include "core/exit_code.hpp"
#include "output/progress.hpp"
#include "output/run.hpp"
#include "output/scene_description.hpp"
#include "output/seam_metrics.hpp"
#include "scene/build.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::app {

namespace {

struct VerifyArguments {
  std::string scene_path;
  std::string out_dir = "out";
  int threads = 0;
};

std::string number(const std::optional<double>& v) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", *v);
  return buf;
}

// One line per metric of every interface; returns the number of failed checks.
int print_table(const std::vector<output::InterfaceReport>& interfaces, std::ostream& out) {
  char line[256];
  std::snprintf(line, sizeof line, "%-15s %-28s %-5s %-19s %-11s %-11s %-6s %s\n", "interface", "leader -> follower",
                "cont.", "metric", "max", "limit", "frame", "result");
  out << line;
  int failed = 0, checked = 0;
  for (const output::InterfaceReport& seam : interfaces) {
    const std::string edges = seam.leader + " -> " + seam.follower;
    bool first = true;
    for (const auto& [check, label] : {std::pair{&seam.gap, "gap [m]"}, std::pair{&seam.angle_degrees, "normal angle [deg]"},
                                       std::pair{&seam.stress_ratio, "stress ratio"}}) {
      const output::SeamCheck& c = *check;
      failed += c.result == "fail";
      checked += c.result == "pass" || c.result == "fail";
      std::snprintf(line, sizeof line, "%-15s %-28s %-5s %-19s %-11s %-11s %-6s %s\n",
                    first ? seam.interface.c_str() : "", first ? edges.c_str() : "",
                    first ? seam.continuity.c_str() : "", label, number(c.max).c_str(), number(c.limit).c_str(),
                    c.frame ? std::to_string(*c.frame).c_str() : "-", c.result.c_str());
      out << line;
      first = false;
    }
  }
  out << (failed ? "FAIL: " + std::to_string(failed) + " of " + std::to_string(checked) + " checks failed\n"
                 : "PASS: all " + std::to_string(checked) + " checks passed\n");
  return failed;
}

int run_verify(const VerifyArguments& a) {
  const scene::Model model = scene::load_model(a.scene_path);
  if (output::scene_seams(model).empty())
    throw scene::SceneError(model.source, "/interfaces",
                            "the scene declares no interfaces: nothing to verify (add \"interfaces\", see "
                            "docs/scene-format.md)");
  output::RunOptions run;
  run.out_dir = a.out_dir;
  run.threads = a.threads;
  run.interactive = output::Progress::stderr_is_terminal();
  std::cerr << "verify coupling: running " << output::describe_scene(model);
  const output::Summary summary = output::run_scene(model, run, std::cerr);
  std::cout << "seam checks of scene \"" << model.name << "\" over " << summary.frames.size() << " frames (model size "
            << output::model_size(model) << " m; series in " << a.out_dir << "/summary.json, metrics.interfaces)\n";
  const int failed = print_table(summary.metrics.interfaces.value_or(std::vector<output::InterfaceReport>{}), std::cout);
  return core::to_int(failed ? core::ExitCode::verify_failed : core::ExitCode::ok);
}

}  // namespace

Command add_verify_command(CLI::App& app) {
  auto args = std::make_shared<VerifyArguments>();
  auto* verify = app.add_subcommand("verify", "Run a scene and check it against its verification limits.");
  verify->require_subcommand(1);
  auto* coupling = verify->add_subcommand(
      "coupling", "Run a scene with patch interfaces like `run`, then print a pass/fail table of every "
                  "interface's seam gap, normal angle and seam stress ratio against the limits in the scene "
                  "(exit 0 all pass, 4 a check failed).");
  coupling->add_option("scene", args->scene_path, "Scene file (JSON) with \"interfaces\"")->required();
  coupling->add_option("--out,-o", args->out_dir, "Output directory")->capture_default_str();
  coupling->add_option("--threads,-j", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  return [args, coupling]() -> std::optional<int> {
    if (!coupling->parsed()) return std::nullopt;
    return run_guarded([&] { return run_verify(*args); });
  };
}

}  // namespace shellfrac::app
