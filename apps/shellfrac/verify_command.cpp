// `shellfrac verify coupling`: runs a coupled scene and checks its seams against the scene's limits.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "apps/shellfrac/budget.hpp"
#include "apps/shellfrac/command.hpp"
#include "core/exit_code.hpp"
#include "output/interrupt.hpp"
#include "output/progress.hpp"
#include "output/run.hpp"
#include "output/scene_description.hpp"
#include "output/seam_metrics.hpp"
#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::app {

namespace {

struct VerifyArguments {
  std::string scene_path;
  std::string out_dir = "out";
  int threads = 0;
  BudgetArguments budget;
};

std::string number(const std::optional<double>& v) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", *v);
  return buf;
}

struct Tally {
  int failed = 0, checked = 0;
};

// One line per metric of every interface.
Tally print_table(const std::vector<output::InterfaceReport>& interfaces, std::ostream& out) {
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
  return {failed, checked};
}

// The whole-scene row on the render mesh: the largest edge stretch of any frame (metrics.peak_edge_stretch)
// against the scene's "verify": {"max_edge_stretch"} (default output::kDefaultMaxEdgeStretch, null: off).
std::optional<double> edge_stretch_limit(const scene::Scene& s) {
  if (!s.verify || !s.verify->max_edge_stretch) return output::kDefaultMaxEdgeStretch;
  return s.verify->max_edge_stretch->value;
}

Tally print_mesh_row(const output::MeshReport& mesh, const std::optional<double>& limit, std::ostream& out) {
  const bool fail = limit && !(mesh.peak_edge_stretch <= *limit);
  char line[256];
  std::snprintf(line, sizeof line, "%-15s %-28s %-5s %-19s %-11s %-11s %-6s %s\n", "render mesh", "whole scene", "",
                "peak edge stretch", number(mesh.peak_edge_stretch).c_str(), number(limit).c_str(),
                std::to_string(mesh.peak_edge_stretch_frame).c_str(), !limit ? "unchecked" : fail ? "fail" : "pass");
  out << line;
  return {fail ? 1 : 0, limit ? 1 : 0};
}

int run_verify(const VerifyArguments& a) {
  const scene::Scene input = scene::load_scene(a.scene_path);
  // Refused before anything big is allocated, as `run` does.
  scene::check_budget(scene::estimate_resources(input), make_budget(a.budget, a.out_dir), input.source);
  const scene::Model model = scene::build(input);
  if (output::scene_seams(model).empty())
    throw scene::SceneError(model.source, "/interfaces",
                            "the scene declares no interfaces: nothing to verify (add \"interfaces\", see "
                            "docs/scene-format.md)");
  output::RunOptions run;
  run.out_dir = a.out_dir;
  run.threads = a.threads;
  run.interactive = output::Progress::stderr_is_terminal();
  std::cerr << "verify coupling: running " << output::describe_scene(model);
  const output::InterruptHandlers handlers;
  const output::Summary summary = output::run_scene(model, run, std::cerr);
  if (summary.status == "interrupted") {
    const int signal = output::interrupt_signal();
    std::cerr << "verify coupling: interrupted at t = " << summary.simulated_seconds << " s; nothing verified\n";
    return 128 + (signal ? signal : 2);
  }
  std::cout << "seam checks of scene \"" << model.name << "\" over " << summary.frames.size() << " frames (model size "
            << output::model_size(model) << " m; series in " << a.out_dir << "/summary.json, metrics.interfaces)\n";
  const Tally seams = print_table(summary.metrics.interfaces.value_or(std::vector<output::InterfaceReport>{}), std::cout);
  const Tally mesh = print_mesh_row(summary.metrics.mesh, edge_stretch_limit(input), std::cout);
  const int failed = seams.failed + mesh.failed, checked = seams.checked + mesh.checked;
  std::cout << (failed ? "FAIL: " + std::to_string(failed) + " of " + std::to_string(checked) + " checks failed\n"
                       : "PASS: all " + std::to_string(checked) + " checks passed\n");
  return core::to_int(failed ? core::ExitCode::verify_failed : core::ExitCode::ok);
}

}  // namespace

Command add_verify_command(CLI::App& app) {
  auto args = std::make_shared<VerifyArguments>();
  auto* verify = app.add_subcommand("verify", "Run a scene and check it against its verification limits.");
  verify->require_subcommand(1);
  auto* coupling = verify->add_subcommand(
      "coupling", "Run a scene with patch interfaces like `run`, then print a pass/fail table of every "
                  "interface's seam gap, normal angle and seam stress ratio, and the render mesh's peak edge stretch, against the limits in the scene "
                  "(exit 0 all pass, 4 a check failed).");
  coupling->add_option("scene", args->scene_path, "Scene file (JSON) with \"interfaces\"")->required();
  coupling->add_option("--out,-o", args->out_dir, "Output directory")->capture_default_str();
  coupling->add_option("--threads,-j", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  add_budget_options(coupling, args->budget, true);
  return [args, coupling]() -> std::optional<int> {
    if (!coupling->parsed()) return std::nullopt;
    return run_guarded([&] { return run_verify(*args); });
  };
}

}  // namespace shellfrac::app
